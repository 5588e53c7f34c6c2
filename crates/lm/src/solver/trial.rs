//! A trial step and its assessment: the plain values that the descent, the assessment of a
//! step and the trust radius pass between them.

use super::step::StepInfo;

/// One trial step, evaluated or restored from the saved good step.
#[derive(Clone, Copy, Debug)]
pub(super) struct Trial {
    pub(super) info: StepInfo,
    /// f at the trial point.
    pub(super) f: f64,
    /// RELDX of the step.
    pub(super) reldx: f64,
    /// The saved good step was taken instead of the last one computed (NL2SOL's GOODX false).
    pub(super) restored: bool,
}

/// DA7SST's judgement of a trial step.
#[derive(Clone, Copy, Debug)]
pub(super) struct Assessment {
    /// f before the step.
    pub(super) f0: f64,
    /// Actual reduction `f0 - f`.
    pub(super) ared: f64,
    /// `ared / PREDUC`.
    pub(super) ratio: f64,
    pub(super) accepted: bool,
    /// The other model (adaptive choice) predicted the actual reduction better.
    pub(super) switch_models: bool,
}
