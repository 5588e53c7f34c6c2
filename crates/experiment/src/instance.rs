//! Building instances: data sets (synthetic or read from files) and parameter layouts.

use std::cell::Cell;
use std::path::Path;
use std::sync::Arc;

use brdf_model::{DataError, DataSet, FilterReport, Layout, ModelError};

use crate::spec::{DataFormat, FileSpec, InstanceSpec, Source};

/// Errors building an instance.
#[derive(Debug, thiserror::Error)]
pub enum InstanceError {
    /// The data file could not be read.
    #[error("instance `{instance}`: {source}")]
    Data {
        /// Instance name.
        instance: String,
        /// The reader's error (names file and line).
        source: DataError,
    },
    /// The model layout is invalid.
    #[error("instance `{instance}`: model: {source}")]
    Model {
        /// Instance name.
        instance: String,
        /// The layout error.
        source: ModelError,
    },
    /// The requested evaluation kernel cannot run here.
    #[error(transparent)]
    Kernel(#[from] brdf_model::KernelError),
    /// Generating a synthetic instance failed (parameters, size or overflow).
    #[error("instance `{instance}`: {source}")]
    Synthetic {
        /// Instance name.
        instance: String,
        /// The generator's error.
        source: brdf_model::ParamError,
    },
    /// The data set is empty after filtering.
    #[error("instance `{instance}`: no samples left ({report})")]
    Empty {
        /// Instance name.
        instance: String,
        /// What the filters dropped.
        report: String,
    },
}

/// An instance ready to run: shared read-only data and the layout to fit.
#[derive(Clone, Debug)]
pub struct BuiltInstance {
    /// The data (shared by every trial of the instance).
    pub data: Arc<DataSet>,
    /// The parameter layout.
    pub layout: Layout,
    /// What the reader's filters dropped (files only).
    pub filter_report: Option<FilterReport>,
}

/// Reads a data file with the spec's reader options and filters.
pub fn load_file(spec: &FileSpec, path: &Path) -> Result<(DataSet, FilterReport), DataError> {
    let format = spec
        .format
        .or_else(|| DataFormat::from_path(path))
        .unwrap_or(DataFormat::Csv);
    let filters = spec.filters();
    match format {
        DataFormat::Cornell => brdf_model::read_cornell(
            path,
            spec.wavelength.unwrap_or(brdf_model::DEFAULT_WAVELENGTH_NM),
            &filters,
        ),
        DataFormat::Csv => brdf_model::read_csv(path, &filters),
        DataFormat::Merl => brdf_model::read_merl(
            path,
            spec.channel.unwrap_or(brdf_model::Channel::Green),
            &filters,
        ),
    }
}

thread_local! {
    static BUILDS: Cell<usize> = const { Cell::new(0) };
}

/// How many instances this thread has built ([`build`] calls). A diagnostic: tests pin that a
/// run builds each instance once.
pub fn builds_on_this_thread() -> usize {
    BUILDS.with(Cell::get)
}

/// Builds every instance of `spec`, in order.
pub fn build_all(spec: &crate::spec::Spec) -> Result<Vec<BuiltInstance>, InstanceError> {
    spec.instances.iter().map(build).collect()
}

/// Builds one instance's data set and layout.
pub fn build(spec: &InstanceSpec) -> Result<BuiltInstance, InstanceError> {
    BUILDS.with(|b| b.set(b.get() + 1));
    let layout = spec.model.layout().map_err(|source| InstanceError::Model {
        instance: spec.name.clone(),
        source,
    })?;
    let (data, filter_report) = match &spec.source {
        Source::Synthetic {
            params,
            samples,
            sigma,
            seed,
            ..
        } => {
            let d =
                brdf_model::try_synthetic(params, *samples, *sigma, *seed).map_err(|source| {
                    InstanceError::Synthetic {
                        instance: spec.name.clone(),
                        source,
                    }
                })?;
            (d, None)
        }
        Source::File { spec: fs, resolved } => {
            let (d, r) = load_file(fs, resolved).map_err(|source| InstanceError::Data {
                instance: spec.name.clone(),
                source,
            })?;
            (d, Some(r))
        }
    };
    if data.is_empty() {
        return Err(InstanceError::Empty {
            instance: spec.name.clone(),
            report: filter_report.map(|r| r.to_string()).unwrap_or_default(),
        });
    }
    Ok(BuiltInstance {
        data: Arc::new(data),
        layout,
        filter_report,
    })
}
