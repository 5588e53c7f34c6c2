pub mod expsum;
pub mod mgh_run;
pub mod nist;
