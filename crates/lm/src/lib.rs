//! Bounded trust-region Levenberg-Marquardt solver in the role of PORT's N2FB (work in progress).
