//! The one step before a run (`brdf-sls run`): lock the results folder, read its results file
//! once, build each instance once, and resolve the best-known RMSEs (and so the relative
//! targets) from what the file recorded or from those same built instances. The runner then
//! works from the returned [`Prepared`]: nothing is read or built twice, and nothing is read
//! before the lock is held.

use std::path::Path;

use brdf_experiment::instance::{BuiltInstance, InstanceError};
use brdf_experiment::spec::Spec;
use brdf_experiment::store::{LockedFolder, StoreError};

/// A run ready to start.
#[derive(Debug)]
pub struct Prepared {
    /// The spec, its best-known RMSEs and relative targets resolved.
    pub spec: Spec,
    /// The results folder, locked, with what its results file held.
    pub folder: LockedFolder,
    /// Every instance, built once (`built[i]` is `spec.instances[i]`).
    pub built: Vec<BuiltInstance>,
    /// Lines to show: instances left without a best-known RMSE, closeness warnings
    /// ([`crate::run_lines`]).
    pub notes: Vec<String>,
}

/// Why a run could not be prepared.
#[derive(Debug, thiserror::Error)]
pub enum PrepareError {
    /// The folder could not be created or locked.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// An instance could not be built.
    #[error(transparent)]
    Instance(#[from] InstanceError),
}

/// Prepares a run of `spec` into `out` (see the module docs).
pub fn prepare(mut spec: Spec, out: &Path) -> Result<Prepared, PrepareError> {
    let folder = LockedFolder::lock(out)?;
    let built = brdf_experiment::instance::build_all(&spec)?;
    let known = crate::recorded_for(&spec, folder.contents());
    let resolved = crate::resolve_built(&mut spec, &known, &built)?;
    let notes = crate::run_lines(&spec, &resolved);
    Ok(Prepared {
        spec,
        folder,
        built,
        notes,
    })
}
