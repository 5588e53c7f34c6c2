//! Building instances: data sets (synthetic, drawn from a suite or read from files) and
//! parameter layouts.

use std::cell::Cell;
use std::path::Path;
use std::sync::Arc;

use brdf_io::DataError;
use brdf_model::{DataSet, FilterReport, Layout, ModelError, Samples};

use crate::spec::{FileSpec, InstanceSpec, Source};

/// Errors building an instance.
#[derive(Debug, thiserror::Error)]
pub enum InstanceError {
    /// The data file could not be read.
    #[error("instance `{instance}`: {source}")]
    Data {
        /// Instance name.
        instance: String,
        /// The reader's error (names file and line).
        source: Box<DataError>,
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
    /// Generating a suite instance failed (sample count, noise or a non-finite value).
    #[error("instance `{instance}`: {source}")]
    Suite {
        /// Instance name.
        instance: String,
        /// The generator's error.
        source: brdf_published::suite::SuiteError,
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

/// An instance ready to run: shared read-only data, the family's samples of it and the
/// layout to fit.
#[derive(Clone, Debug)]
pub struct BuiltInstance {
    /// The data (shared by every trial of the instance).
    pub data: Arc<DataSet>,
    /// The model family's per-sample columns of the data, prepared once (shared likewise).
    pub samples: Arc<Samples>,
    /// The parameter layout.
    pub layout: Layout,
    /// What the reader's filters dropped (files only).
    pub filter_report: Option<FilterReport>,
}

/// Generating parameters checked against their family's box with the bounds the model widens
/// (a spec's `model.bounds`: an exponent of 16,600 is generated when the model admits it).
struct Within<'a> {
    params: &'a brdf_model::Params,
    bounds: &'a std::collections::BTreeMap<String, [f64; 2]>,
}

impl brdf_model::Reflectance for Within<'_> {
    fn value(&self, u: [f64; 3], v: [f64; 3]) -> f64 {
        self.params.value(u, v)
    }
    fn check(&self) -> Result<(), brdf_model::ParamError> {
        self.params
            .validate_within(|name| self.bounds.get(name).map(|b| (b[0], b[1])))
    }
}

/// Reads a data file with the spec's format ([`FileSpec::format_for`]: from the extension
/// unless named; never a guess) and filters.
pub fn load_file(spec: &FileSpec, path: &Path) -> Result<(DataSet, FilterReport), DataError> {
    let format = spec.format_for(path).map_err(|message| DataError::Binary {
        path: path.to_path_buf(),
        message,
    })?;
    brdf_io::read(path, &format, &spec.filters())
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
            suite: Some(s),
            ..
        } => {
            let d = s
                .generate(params, *samples, *sigma, *seed)
                .map_err(|source| InstanceError::Suite {
                    instance: spec.name.clone(),
                    source,
                })?;
            (d, None)
        }
        Source::Synthetic {
            params,
            samples,
            sigma,
            seed,
            ..
        } => {
            let truth = Within {
                params,
                bounds: &spec.model.bounds,
            };
            let d =
                brdf_model::try_synthetic(&truth, *samples, *sigma, *seed).map_err(|source| {
                    InstanceError::Synthetic {
                        instance: spec.name.clone(),
                        source,
                    }
                })?;
            (d, None)
        }
        Source::File { spec: fs, resolved } => {
            let (d, r) = load_file(fs, resolved).map_err(|e| InstanceError::Data {
                instance: spec.name.clone(),
                source: Box::new(e),
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
        samples: Arc::new(layout.prepare(&data)),
        data: Arc::new(data),
        layout,
        filter_report,
    })
}
