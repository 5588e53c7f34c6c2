pub mod expsum;
pub mod nist;
