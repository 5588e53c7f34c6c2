//! The Lafortune BRDF model, parameter layouts, data sets and RMSE (work in progress).
