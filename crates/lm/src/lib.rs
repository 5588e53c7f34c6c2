//! Bounded trust-region Levenberg-Marquardt solver in the role of PORT's N2FB.
//!
//! Minimises `f(x) = 0.5 * sum_i r_i(x)^2` subject to `lower <= x <= upper` and reports *why* it
//! stopped with N2FB's return codes, because the search algorithms built on it (AED, AERS)
//! branch on them.
//!
//! ```
//! use bounded_lm::{Options, Problem, Solver};
//! struct Line; // fit y = a + b t to three points
//! impl Problem for Line {
//!     fn residual_count(&self) -> usize { 3 }
//!     fn parameter_count(&self) -> usize { 2 }
//!     fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
//!         for (i, ri) in r.iter_mut().enumerate() {
//!             *ri = x[0] + x[1] * i as f64 - [1.0, 3.0, 5.0][i];
//!         }
//!         true
//!     }
//!     fn jacobian(&mut self, _x: &[f64], jac: &mut [f64]) -> bool {
//!         jac.copy_from_slice(&[1.0, 1.0, 1.0, 0.0, 1.0, 2.0]); // column-major
//!         true
//!     }
//! }
//! let mut x = [0.0, 0.0];
//! let (lower, upper) = ([f64::NEG_INFINITY; 2], [f64::INFINITY, 1.5]);
//! let report = Solver::new().solve(&mut Line, &mut x, &lower, &upper, &Options::default()).unwrap();
//! assert!(report.outcome.is_success());
//! assert_eq!(x[1], 1.5); // the optimum lies on the upper bound of b
//! ```
//!
//! # Algorithm
//! Each iteration evaluates the Jacobian `J` (column-major, `jac[j*m + i] = dr_i/dx_j`), updates
//! the scaling `D`, and computes a Householder QR of the scaled Jacobian `J D^-1 = Q R`. The step
//! solves the trust-region subproblem `min model(s)` subject to `||D s|| <= radius` by the
//! More-Sorensen/Hebden iteration on the Levenberg-Marquardt parameter `lambda`: for the
//! Gauss-Newton model the shifted systems are factored by Givens rotations of
//! `[R; sqrt(lambda) I]` (MINPACK's qrsolv), so `J^T J` is never formed and its squared condition
//! number never matters; a rank-deficient `R` simply has no Gauss-Newton step (lambda > 0 is
//! always well posed). When the minimum-norm Gauss-Newton step of a rank-deficient `R` lies
//! inside the region, no `lambda` reaches the boundary; by default the iteration then stops
//! once the steps stop growing, as MINPACK's `lmpar` does
//! ([`Options::stop_at_minimum_norm_step`], off in the searches). A step is accepted when `f`
//! decreases by more than 1e-4 of the predicted reduction. A rejected step gets one
//! second-order correction before the radius shrinks ([`Options::second_order_correction`],
//! ours, off in [`Options::n2fb`] and in the searches): the residuals' departure from the linear
//! model at the rejected point, `e = r(x + s) - r(x) - J s`, gives `c` minimising
//! `||J c + e||^2 + lambda ||D c||^2`, and `s + c` is evaluated and accepted by the same test
//! against `s`'s predicted reduction.
//!
//! With fewer residuals than free variables (`m < n`: a 25-row subsample of a many-lobe model)
//! `R` has only `m` nonzero rows, and the shifted systems are solved in their dual form
//! `z = -R_m^T (R_m R_m^T + lambda I)^-1 u_m`, an `m x m` Cholesky per `lambda` instead of
//! `O(n^3)` Givens work: the same step (tested against the Givens form), at `O(m^3 + m n)` per
//! `lambda` (one step at 251 parameters on 25 rows once took seconds). After a failed
//! evaluation the solver asks [`Problem::should_stop`] before retrying with a smaller radius, so
//! a caller that refuses evaluations once its budget is spent ends the solve at once (code 11).
//!
//! **Trust radius** ([`RadiusUpdate`]). The default is N2FB's rule (NL2SOL's DA7SST with
//! PORT's DG7ITB): RADFAC is Fletcher's factor 0.1..0.5 after a rejected step or one that
//! achieved less than 0.1 of the predicted reduction; 2..4 when the reduction is at least 0.75
//! of the linear prediction `-g^T s` (about 1.5 times PREDUC for a near-Gauss-Newton step) and
//! the radius was not decreased earlier in the iteration; otherwise 1, raised to 2 by DG7ITB's
//! gradient tests when the model predicted the new gradient well (`||D^-1 (H s + g0 - g)|| <=
//! 0.5 ||D^-1 g||`) or the slope along the step is still `g^T s < 0.75 g0^T s`. After an
//! accepted step the radius becomes `t = RADFAC * ||D_new s||` (updated scaling) when RADFAC < 1
//! or `t` exceeds it. When the radius is to grow after a step that was not the Newton step (and
//! the Newton step is at least twice as long and predicts at least 1.2 times the reduction
//! obtained), the longer step is tried at once from the same point without a new Jacobian
//! (DA7SST's IRC = 5; evaluated only if it predicts more than 1.2 times the reduction obtained,
//! DG7ITB), and the better of the two is kept. Unlike NL2SOL we try at most one longer step per
//! iteration, and none once the adaptive model choice may switch models
//! ([`RadiusUpdate::Nl2sol`] documents why: both measured worse on NIST or MGH).
//! [`RadiusUpdate::Classic`] is the ratio
//! rule of the first version (0.1..0.5 after a rejection, halve below ratio 0.25, double above
//! 0.75).
//!
//! **Scaling.** `D_i = max(0.6 D_i, ||J_i||_2)`: N2FB's adaptive rule with the column 2-norm of
//! the original NL2SOL instead of N2FB's column max; 1 is used for a column whose norm is below
//! 1e-6. The factor 0.6 is NL2SOL's DFAC, [`Options::scaling_decay`] (1 gives MINPACK's
//! never-decreasing scaling; see "Robustness" for what each costs). Measured on NIST with default budgets, the Gauss-Newton model and the classic radius
//! rule (before N2FB's radius rule was added): this rule 50/54,
//! N2FB's column max 44/54 (it let the Lanczos fits drift into the degenerate region where two
//! exponentials merge), a never-decreasing 2-norm as in MINPACK 49/54.
//! By default ([`Options::secant_scaling`]) the diagonal of the secant term `S` enters too, as in
//! NL2SOL and N2FB: `D_i = max(0.6 D_i, sqrt(||J_i||^2 + S_ii))` where `S_ii > 0`, so `D`
//! follows the diagonal of `J^T J + S`; `S` is kept by the secant update whatever the model and
//! updated before the scaling. Unlike N2FB, `S` enters only once it has had
//! [`Options::secant_scaling_delay`] (default 2) updates per parameter, so short solves keep the
//! Jacobian scaling (see "Robustness" for why it matters and why the delay).
//! [`Options::n2fb`] is N2FB's configuration: the adaptive model, `S` in the scaling at once.
//!
//! **Step models** ([`StepModel`]). `GaussNewton` uses `J^T J`. `Adaptive` (the default) is
//! NL2SOL's scheme: a secant approximation `S` of the second-order term `sum r_i H_i` is kept by
//! the sized Dennis-Gay-Welsch update, and after each step the solver switches between the
//! Gauss-Newton and the augmented model `J^T J + S` when the other one predicted the actual
//! reduction better (retrying a failed step once with the other model); the augmented model is
//! solved by Cholesky factorizations of the scaled `H + lambda I` (it may be indefinite).
//! The relative-function test uses the Gauss-Newton reduction `0.5 ||P_J r||^2` (zero at
//! every stationary point, undefined where `J` is singular), so the augmented model cannot claim
//! convergence merely because it predicts no decrease (it did so on BoxBOD start 1 before); the
//! augmented model's own Newton reduction (N2FB's NREDUC) counts too, but only where the
//! Gauss-Newton step exists (without it, Brown and Dennis ended with code 7 at its minimum:
//! near a large-residual minimum the Gauss-Newton reduction shrinks only linearly).
//! The switch is considered only after a poor step (actual reduction at most 0.1 of PREDUC, the
//! steps after which RADFAC < 1): after a good step the current model is kept. This is ours:
//! NL2SOL's NL2ITR and PORT's DG7ITB consider the switch after every assessed step (IRC 1 to 4,
//! good steps included) and switch only when the other model's error `|PREDUC' - ared|` is
//! below 1/FUZZ of the current one's (FUZZ = 1.5, DV7DFL). Measured against the default
//! (2026-12-02, `mgh_table`, `nist_table`): their rule scored 68/78 MGH unbounded (Meyer and
//! Gulf Research from x0 lost to the iteration limit, nothing gained) and 51/54 NIST; FUZZ alone
//! (still after poor steps only) 69/78 (Gulf Research from x0 lost).
//! Measured on NIST with default budgets (`examples/nist_table.rs`), without the secant scaling:
//! Gauss-Newton 52/54 correct with 1259 iterations and 1564 residual evaluations over the 54
//! runs, Adaptive 52/54 with 1874 and 2177; on MGH (`examples/mgh_table.rs`, 78 unbounded runs)
//! Gauss-Newton 66/78, Adaptive 68/78. With the delayed secant scaling and switching from the
//! first update the adaptive model scores 50/54 and 67/78, as [`Options::n2fb`] 51/54 and 69/78.
//! **The default switches only after [`Options::adaptive_delay`] (2) secant updates per
//! parameter** (ours, not N2FB's): until then a solve is exactly a Gauss-Newton one, so the
//! searches' short descents are unchanged, and long solves of large-residual problems get the
//! augmented model's end game: NIST 52/54, MGH 70/78, Brown and Dennis in 23 / 27 iterations
//! (see "Robustness" and the table below; 71/78 since the second-order correction).
//!
//! # Robustness (issue 14): what N2FB did that this solver did not
//! Sources: J. E. Dennis, D. M. Gay and R. E. Welsch, *An adaptive nonlinear least-squares
//! algorithm*, ACM TOMS 7(3), 348-368, 1981 (NL2SOL: the adaptive choice between the
//! Gauss-Newton and the augmented model, the sized secant update, the radius rule); D. M. Gay,
//! *Usage summary for selected optimization routines*, Computing Science Technical Report 153,
//! AT&T Bell Laboratories, 1990 (PORT's N2FB, N2GB: bounds, return codes, defaults).
//! - **The model switch never happened** (found on Brown and Dennis and Penalty II, MGH 16 and
//!   24). The other model's prediction was computed with the wrong sign of `0.5 s^T S s`, so the
//!   augmented model always looked worse and [`StepModel::Adaptive`] stayed on the Gauss-Newton
//!   model. On Brown and Dennis (large residual, `f* = 4.29e4`) the Gauss-Newton model misses the
//!   positive curvature `sum r_i H_i`: steps zigzag in `x3, x4` while `x1, x2` creep, and the
//!   solve stopped at the iteration limit with f = 6.4e5 (150 iterations). Fixed (and the switch
//!   gated as above): Brown and Dennis from x0 in 26 iterations (f = 42911.10, code 7) and from
//!   10 x0 in 30 (code 4) with `Adaptive`; the Gauss-Newton model alone still creeps.
//! - **N2FB's scaling includes the secant term; ours did not** (found by comparing, iteration
//!   by iteration, Brown and Dennis and Penalty II, MGH 16 and 24, with NL2SOL 2.2's DUPDAT and
//!   PORT's DD7UPD). Both update `D` from the diagonal of the augmented Hessian: DUPDAT sets
//!   `t = ||J_i||_2`, then `t = sqrt(t^2 + S_ii)` if `S_ii > 0`, and `D_i = max(DFAC D_i, t)`
//!   (DFAC = 0.6); DD7UPD uses `max(max_k |J_ki|, sqrt(S_ii))`. The secant matrix `S` exists
//!   in N2FB whatever model the step uses. Ours took the Jacobian column norms only. On a
//!   large-residual problem the Gauss-Newton diagonal misses most of the curvature: on Brown
//!   and Dennis (residuals `a_i^2 + b_i^2` with `|a_i| >> |b_i|`) the curvature of f in x3, x4
//!   is about `2 sum r_i` while `(J^T J)_33 = 4 sum b_i^2` is small, so `D` was about
//!   (144, 306, 7, 5) after 30 iterations and the trust region, round in `D`-scaled
//!   coordinates, allowed x3, x4 to move by about 1 (the Gauss-Newton step overshoots there:
//!   the iterates zigzagged x3 = -0.6, 0.3, -0.7, 0.3, ... with actual/predicted reduction
//!   alternating near 0.5 and 0.1, or a rejection) while x1 moved by about 0.03 per iteration,
//!   from 25 to 18.7 in 33 iterations (it must reach -11.6): 150 iterations, f = 6.4e5.
//!   With `S` in the scaling `D_3, D_4` rise to about 40 and 25, and the solve reaches the
//!   minimum: [`Options::n2fb`] in 21 iterations from x0 and 24 from 10 x0 (code 4; PORT: 15
//!   to 16), the Gauss-Newton model with it from the first update in 83 and 72, with the
//!   default delay in 71 and 81 (the Gauss-Newton model converges only linearly near a
//!   large-residual minimum: from the first update, f was within 4e-4 relative of the minimum
//!   after 37 iterations, and the rest was the approach to RFCTOL). Unit scaling (`D = I`, scipy's default) also solves Brown
//!   and Dennis (20 iterations) but drops NIST to 48/54. PORT's max form
//!   `max(||J_i||_2, sqrt(S_ii))` instead of DUPDAT's: Gauss-Newton 69/78 MGH and 52/54 NIST,
//!   Adaptive 68/78 with one success code on a wrong answer, so DUPDAT's form is used.
//!   **The delay** (ours): with `S` in the scaling from the first update the searches were
//!   slower, so `S` enters after [`Options::secant_scaling_delay`] updates per parameter.
//!   Sample-evaluations to RMSE 0.11 on the paper's tuning instance (`cargo run --release -p sls
//!   --example tuning_bench -- --seeds 200 --cutoff 10 --algorithms aed,rpls --gauss-newton
//!   [--no-secant-scaling] [--secant-delay K]`, medians; MGH unbounded solved and NIST correct
//!   with the Gauss-Newton model):
//!
//!   | secant scaling | AED | RPLS | MGH | NIST |
//!   |---|---|---|---|---|
//!   | none (before) | 96,905 | 710,000 | 66/78 | 52/54 |
//!   | from the first update (N2FB) | 111,436 | 700,000 | 70/78 | 51/54 |
//!   | after p updates | 103,035 | 740,000 | - | 52/54 |
//!   | after 2p updates (default) | 96,905 | 690,000 | 70/78 | 52/54 |
//!   | after 3p updates | 96,905 | 720,000 | 71/78 | 52/54 |
//!
//!   (This table was measured with the Gauss-Newton model, the default before the delayed
//!   adaptive model below.)
//!
//!   With 1000 seeds: AED 102,569 without, 110,519 from the first update (90th percentile
//!   520,683 and 1,252,490) and 102,569 with the default; RPLS 710,000 without and 690,000 with
//!   the default. AED's descents (10 iterations on subsamples) are shorter than the delay, so
//!   they are unchanged; RPLS's full-data descents are long enough to use `S`. The delay was
//!   chosen on these measurements (there is no held-out set): 2p for the searches; the 71/78 at
//!   3p differs from 70/78 by one creeping run (Osborne 1 from 10 x0), so we do not claim it.
//!   With the adaptive model the searches stay slower with or without the secant term: AED
//!   113,127 (199/200 reached) with the default delay, 116,405 (198/200) as N2FB; RPLS 770,000
//!   and 800,000.
//! - **Radius factors and the Levenberg parameter were compared too and match N2FB**: DA7SST's
//!   Fletcher decrease factor (0.1..0.5), the increase to 2..4 only when the reduction is at
//!   least 0.75 of `-g^T s` and the radius was not decreased in the iteration, the retry of a
//!   longer step (IRC = 5), and DG7ITB's gradient tests for RADFAC = 1; `lambda` is found by
//!   the More-Hebden iteration to within 10% of the radius (NL2SOL's EPSLON = 0.1) and warm
//!   started from the last value. The classic ratio rule does not solve Brown and Dennis either
//!   (150 iterations). What remains on Penalty II (n = 10) is a curved valley: steps of scaled
//!   length about 5e-3 are rejected (actual/predicted -8) while steps of 5e-4 reach
//!   actual/predicted 0.93 to 1.0, and with `lambda` small `-g^T s` is about twice PREDUC, so
//!   by N2FB's rule the radius grows only after a reduction of 1.5 times PREDUC: it creeps at
//!   the scale of the valley's curvature (f within 5e-5 relative of the minimum at the budget
//!   from x0, with or without the secant scaling); both models creep there.
//! - **How fast the scaling may fall** ([`Options::scaling_decay`], NL2SOL's DFAC; measured
//!   2026-12-03 with `mgh_table -- OUT default scaling-decay=F`, `nist_table` and
//!   `tests/robustness.rs`, before the second-order correction existed: the same as with
//!   `no-correction` now). Penalty II creeps (below) while `D` follows its shrinking
//!   columns down; with MINPACK's never-decreasing scaling (Moré 1978) it is solved from x0 in
//!   56 iterations and from 10 x0 in 62, and Osborne 1 from 10 x0 in 122. But the count does
//!   not rise steadily with the factor, and each value above 0.6 costs something elsewhere:
//!
//!   | DFAC | MGH unbounded solved | success code on a wrong answer | boxed KKT | NIST correct / iterations (54 runs) | Brown-Dennis iterations | `tests/robustness.rs` |
//!   |---|---|---|---|---|---|---|
//!   | 0.6 (N2FB, default) | 70/78 | 0 | 74/78 | 52/54 / 1370 | 23 / 27 | passes |
//!   | 0.7 | 70/78 | 0 | 74/78 | 52/54 / 1547 | 26 / 22 | passes |
//!   | 0.8 | 69/78 | 1 (Trigonometric, 10 x0: code 4 at a local minimum) | 74/78 | 52/54 / 1505 | 21 / 22 | fails (that code 4) |
//!   | 0.9 | 71/78 | 0 | 74/78 | 52/54 / 1576 | 24 / 21 | passes |
//!   | 1 (MINPACK) | 71/78 | 0 | 74/78 | 52/54 / 1494 | 30 / 26 | fails: the steep exponential `a e^(bt)` from b = 30 ends with code 7 at f = 35, far from the solution, because `D_b` stays at its start value ~1e13 |
//!
//!   With 1 the solver gains Penalty II (n = 10) from both starts, Osborne 1 from 10 x0 and
//!   Meyer from x0 (code 4 instead of the iteration limit at the minimum), and loses Gulf
//!   Research from x0 and Penalty II (n = 4) from 10 x0 to the iteration limit. The searches'
//!   descents were slower with it (`tuning_bench -- --seeds 1000 --scaling-decay 1`, see the
//!   README). Since the 71s were found by trying factors on the very runs that are counted,
//!   and 0.8 between them loses two, we read them as noise around 70, not as a better rule,
//!   and keep N2FB's 0.6.
//! - **A second-order correction of rejected steps** (ours, 2026-12-03;
//!   [`Options::second_order_correction`]). The curved valleys below (Penalty II, Osborne 1)
//!   creep because every step longer than the valley's curvature fails, while N2FB's rules
//!   shrink the radius back each time. A rejected step has already measured the curvature the
//!   models miss: `e = r(x + s) - r(x) - J s` is about `0.5 s^T H_i s` per residual. The
//!   correction `c = argmin ||J c + e||^2 + lambda ||D c||^2` (the second-order correction of
//!   SQP methods; equally geodesic acceleration with the trial point as its finite difference)
//!   bends the step back onto the valley at the cost of one residual evaluation and no
//!   Jacobian, so unlike the geodesic acceleration below it spends nothing on steps that were
//!   accepted anyway. It is tried when every variable is free and `||D c|| <= 0.75 ||D s||`
//!   (GSL's `avmax`, not tuned here), and kept when `s + c` passes the acceptance test against
//!   `s`'s PREDUC. Measured with `mgh_table -- OUT [config] [no-correction]` and `nist_table`:
//!
//!   | configuration | MGH unbounded, without -> with | boxed KKT | iterations, 78 unbounded runs | NIST correct / iterations, 54 runs |
//!   |---|---|---|---|---|
//!   | default | 70 -> 71/78 | 74 -> 75/78 | 2536 -> 2251 | 52 -> 52/54 / 1370 -> 964 |
//!   | Gauss-Newton | 70 -> 71/78 | 74 -> 74/78 | 2421 -> 2291 | 52 -> 52/54 / 1251 -> 971 |
//!   | Gauss-Newton, no secant scaling | 66 -> 65/78 | 68 -> 68/78 | 2791 -> 2733 | 52 -> 52/54 / 1259 -> 945 |
//!   | Adaptive switching at once | 67 -> 70/78 (one success code on a wrong answer: Beale from 10 x0, code 3 at f = 0.22605 on its valley to infinity) | 73 -> 73/78 | 2779 -> 2382 | 50 -> 51/54 / 1861 -> 1314 |
//!   | MINPACK's scaling (`scaling_decay` 1) | 71 -> 72/78 | 74 -> 74/78 | 2429 -> 1970 | 52 -> 52/54 / 1494 -> 1079 |
//!   | N2FB's configuration with it | 69 -> 71/78 | 73 -> 74/78 | 2685 -> 2382 | - |
//!
//!   With the default it gains Penalty II (n = 10) from x0 (107 iterations, code 4) and
//!   Osborne 1 from 10 x0 (62 iterations, code 4), and loses Gulf Research from x0 (142
//!   iterations and code 6 without it; the iteration limit at f = 4.1e-3 with it). Penalty II
//!   (n = 10) from 10 x0 ends at the evaluation limit within 3.6e-5 relative of its minimum
//!   (the table's test is 1e-5). The 0.75 was taken from GSL; 0.25, 0.5, 1, 2 and no limit
//!   score 70, 70, 71, 70 and 70 of the 78 unbounded runs, NIST 52/54 with 954 to 1008
//!   iterations: the gain in iterations is robust, the 71st solved run is at the margin. A
//!   variant that kept the rejected step's model-switch decision instead of judging the
//!   corrected step afresh scored 70/78 and 1046 NIST iterations; one that also corrected
//!   steps with held variables (on the free ones) left NIST and the unbounded count as they
//!   are but solved fewer boxed runs (KKT 74/78 with the default, 73/78 Gauss-Newton, 72/78
//!   adaptive at once), so it is tried only with every variable free. The searches'
//!   descents keep it off: on the tuning instance (200 seeds, `tuning_bench -- --algorithms aed,rpls
//!   [--second-order-correction]`) AED's median sample-evaluations to RMSE 0.11 rose from
//!   104,333 to 113,480 and its 90th percentile from 441,796 to 743,212 (RPLS 710,000 ->
//!   720,000). `tests/robustness.rs` checks both valleys with and without it; the golden
//!   file pins the default without it (`no-correction`), bit for bit the former default.
//! - **Geodesic acceleration was tried and dropped** (Transtrum and Sethna 2012; GSL's
//!   `lmaccel`): the step `v + a/2`, where `a` solves the shifted system for the second
//!   directional derivative of the residuals along `v` (one extra residual evaluation). GSL
//!   2.7 (`gsl_multifit_nlinear_trust`, Moré scaling) showed why it was worth a try: it
//!   reached Penalty II's minimum (n = 10) from x0 in 20 iterations instead of 80 without it,
//!   and Osborne 1's from 10 x0 in 39 instead of 107, at more residual evaluations (123
//!   against 115 and 169 against 142); but Brown and Dennis from 10 x0 took 494 instead of 50.
//!   Built into this solver for Gauss-Newton steps that no bound cut (2026-12-03), with the
//!   NL2SOL radius rule it solved 65 of the 78 unbounded MGH runs instead of 70, one of them
//!   ending with a success code on a wrong answer: the extra evaluations used up the budget
//!   of 200 (Penalty II stopped at the evaluation limit after 81 iterations, not nearer the
//!   minimum), and many accelerations exceeded GSL's `||a|| <= 0.75 ||v||`. It is not kept.
//! - **Singular convergence at a round-off step** (our change, not in N2FB): N2FB's test step
//!   has scaled length LMAXS = 1; when the Jacobian columns are huge, `||D x|| >> 1` and that
//!   step is a round-off change of x, so PREDUC is tiny relative to f although the gradient is
//!   large. MGH's Jennrich and Sampson from 10 x0 (f = 2.8e34) and Chebyquad (n = 8) from 10 x0
//!   returned code 7 after 1 iteration and 2 evaluations at the start. By default the test
//!   step is now at least `||D x||` long ([`Options::singular_radius_at_least_x`]), so code 7
//!   no longer fires there; false convergence (code 8, an honest failure code) does, because
//!   the first step is below RELDX = 100 eps. **The searches' descents use N2FB's test**
//!   (the option off, `sls::DescentModel::options`): there a code 7 at a hopeless start ends
//!   the descent at once, which is cheaper than letting it run. Measured with one build
//!   (`tuning_bench`, the option off against `--singular-radius-at-least-x`): on the tuning
//!   instance (1000 seeds, target 0.11) AED's median sample-evaluations 111,464 -> 108,292 and
//!   90th percentile 1,144,807 -> 437,236, RPLS 730,000 -> 700,000 (p90 2,990,000 ->
//!   2,570,000); on the two-lobe cross instance without noise (100 seeds, target 0.02, 2 s)
//!   AED 2,007,622 -> 1,250,764 (99 -> 100 of 100 reached), RPLS 1,940,000 -> 1,800,000; with
//!   noise (sigma 0.1, target 0.1, 2 s) RPLS 2,160,000 -> 1,870,000 (100 seeds) but AED
//!   reached the target in 162 instead of 175 of 300 trials within the cutoff, the one case
//!   that got worse. `tests/robustness.rs` checks that N2FB's test ends the steep exponential
//!   and Jennrich-Sampson from 10 x0 with code 7 at the start and the default does not.
//!   [`Options::lift_round_off_radius`] lifts such a round-off first radius to
//!   `sqrt(eps) ||D x||`, and then both are solved; it is off by default because inside the
//!   searches these are hopeless random starts that should end at once: with it always on,
//!   AED's median sample-evaluations to RMSE 0.11 on the paper's tuning instance (1000 seeds)
//!   were 113,273 and RPLS's 920,000, against 105,062 and 700,000 before this session's solver
//!   changes and 102,569 and 710,000 with it off (`cargo run --release -p sls --example
//!   tuning_bench -- --seeds 1000 --cutoff 10 --algorithms aed,rpls`; evaluation counts are
//!   deterministic). `tests/robustness.rs` reproduces both. False convergence is not gated by the gradient: it
//!   needs RELDX at round-off after a failed step, and on noisy residuals (large difference
//!   gradients) code 8 is N2FB's correct answer.
//! - **Numerically dead columns faked convergence** (found by brdf-stress on 25-sample
//!   subsamples of the BRDF tuning instance from mid-box starts, 4 of 40 quick cases): a lobe
//!   with `d^n ~ 1e-150` everywhere has Jacobian columns of that size, scaled by `D = 1` (the
//!   floor), next to a live `kd` column. The Householder QR squared them into underflow
//!   (`inf`/NaN in `R` and `Q^T r`), the NaN gradient made the subproblem return a zero step
//!   "with zero predicted reduction", and that was reported as relative function convergence
//!   (code 4) after one iteration at the start, where moving `kd` alone removes ~98% of f.
//!   Fixed in four places: the QR rescales a column whose norm is below 1e-140 or above 1e140
//!   before reflecting it; a scaled column whose max-abs entry is at most `eps` times the
//!   largest is *dead*: zeroed before the QR and its variable held like one on a bound (left
//!   in, the near-singular `R` made the subproblem move the dead variables by garbage amounts,
//!   with negative PREDUC); while a dead variable is not held by a bound the Gauss-Newton model
//!   counts as singular (no Newton step, NREDUC undefined), so codes 3 and 4 cannot fire and the
//!   solve ends with 7 once the live variables have converged, which is N2FB's answer for a
//!   zero column; and code 4 (in the convergence test and for a zero step) additionally needs
//!   the scaled projected gradient, recomputed as `J^T r` from the Jacobian, to satisfy
//!   `||D_F^-1 g_F|| <= 10 sqrt(p RFCTOL) ||r||`, which a correctly computed NREDUC `<= RFCTOL
//!   f` implies (`||R|| <= sqrt(p)` for unit scaled columns), so the gate never blocks a
//!   genuine code 4. A non-finite model gradient no longer counts as stationary.
//!   `tests/dead_columns.rs` reproduces it (two dead exponential lobes and a live `kd`); the
//!   stress cases now end with code 7 after 3 iterations at RMSE ~3e-3 instead of code 4 at
//!   0.36. NIST and MGH counts are unchanged (golden: only MGH17 start 1 moved, still code 7
//!   at the same f, in 11 iterations and 32 evaluations instead of 13 and 41).
//!   **The hold is an option** ([`Options::hold_dead_columns`], on by default and in
//!   [`Options::n2fb`], off in the searches' descents; N2FB has no such rule). Found when
//!   the paper's figures were re-run on 2026-12-02: with the hold, AED on the two-lobe cross
//!   brushed metal instance needed 9 times the sample-evaluations of the code before these
//!   changes (same seeds: median 6.2e6 with the avx2 kernel against 6.9e5 with the old code's
//!   own kernel choice, 100 trials of `experiments/fig16-synthetic.toml`'s instance, target
//!   0.02), because a lobe that is dead
//!   on a subsample stays dead for the whole descent (the effect is measured; that the
//!   rounding-sized moves of the free variables used to revive such lobes is our reading of
//!   it). The rest of the protection (the QR's rescaling, the gradient
//!   gate on code 4, no stationarity from a non-finite gradient) stays on in every
//!   configuration, so with dead columns free no success code (3 to 6) fires away from a
//!   stationary point; but the steps can be wasted on the dead variables and end with code 7
//!   there (`tests/dead_columns.rs` checks both configurations). In a search code 7 only
//!   shrinks the subsample, so the searches trade it for the measured speed; a library user
//!   keeps the hold.
//! - **Interrupts**: [`Problem::should_stop`] is asked once per iteration and after every
//!   failed evaluation, and ends the solve with [`Outcome::Interrupted`] (code 11, NL2SOL's
//!   STOPX code).
//! - **Symmetric saddles are left to the caller** (a documented choice, not an oversight): two
//!   exchangeable lobes started identical stay identical, because every step of a
//!   Gauss-Newton-type method is equivariant under exchanging them (equal Jacobian columns give
//!   equal step components); N2FB behaves the same. Breaking the tie inside the solver would
//!   need a random perturbation, that is a hidden draw that makes a solve depend on more than
//!   its inputs, or a deterministic one that favours one lobe. The search layer (crate `sls`)
//!   never starts there: every start draws each lobe independently from a continuous
//!   distribution, so identical lobes have probability zero, and a descent that collapses two
//!   lobes is one of many restarts. brdf-stress keeps the case ("two identical lobes",
//!   rank-deficient `J`) to check that it ends with an honest code at the symmetric fit.
//!
//! # Bounds
//! An active-set method as in N2FB: `x` is feasible at every evaluation. A variable on a bound
//! whose gradient points out of the box is held; the subproblem is solved on the free
//! variables; when the step reaches a bound it is cut there, that variable is held at the bound
//! and the rest of the step is re-solved from the cut point (model gradient `g + H s`, remaining
//! radius). Starts on a bound and optima on a bound work. A start outside the box is
//! **projected** onto it (not an error); inconsistent bounds (`lower > upper`, NaN,
//! `lower = +inf`) are [`SolveError::InconsistentBounds`].
//!
//! **Failed evaluations.** [`Problem::residuals`] returning `false`, or non-finite residuals,
//! reject the step and shrink the radius to half the step length; a failed Jacobian at an
//! accepted point returns to the previous point and halves the radius. Only at the start is a
//! failure an error ([`SolveError::StartNotEvaluable`]).
//!
//! # Return codes
//! After every trial step (N2FB's assessment; `f0` = f before the step, PREDUC = predicted
//! reduction of the step, NREDUC = predicted reduction of the full Gauss-Newton step, negative
//! when it does not exist, RELDX = `max_i D_i|x_i - x0_i| / max_i D_i(|x_i| + |x0_i|)`):
//! - the convergence tests run only when the model is trusted: actual reduction `<= 2 PREDUC`;
//! - **3 X-convergence**: the step was the Newton step, it was accepted and RELDX `<= x_tol`.
//!   As N2FB's `STPPAR = 0`, "Newton step" refers to the last sub-step solved: a step cut at a
//!   bound whose remainder, re-solved on the remaining free variables, is the Newton step
//!   counts (otherwise a descent that reaches a face of the box could not x-converge on it);
//! - **4 relative function convergence**: `0 < NREDUC <= rel_function_tol * |f0|`, NREDUC being
//!   the Gauss-Newton reduction on the free variables (as N2FB: held variables, and variables on
//!   a bound whose step leaves the box at once, are excluded; or both
//!   reductions zero; also returned when the projected gradient is exactly zero);
//! - **5**: both 3 and 4;
//! - **7 singular convergence**: `PREDUC <= singular_tol * |f0|` and either `||D s|| >
//!   singular_radius` or the step was the Newton step; otherwise the step is re-solved at radius
//!   `singular_radius` *without evaluating f* and 7 is returned if that step's PREDUC is still
//!   `<= singular_tol * |f0|`; by default the test radius here is `max(singular_radius,
//!   ||D x||)` ([`Options::singular_radius_at_least_x`]; see "Robustness");
//! - **6 absolute function convergence**: `f < abs_function_tol` after an accepted step (or at
//!   the start);
//! - **8 false convergence**: after a rejected or poor (ratio < 0.1) step, RELDX `<=
//!   false_conv_tol` (the radius shrank to round-off without progress);
//! - **9** evaluation limit (checked before each residual evaluation; the start counts),
//!   **10** iteration limit (checked before each Jacobian evaluation), **11** interrupted by
//!   [`Problem::should_stop`] (asked before each Jacobian evaluation).
//!
//! Precedence: 3/4/5 over 7 over 6 over 8. Defaults ([`Options::default`]) are PORT's.
//! The forward-difference adapter [`ForwardDifference`] counts its evaluations apart, as N2FB
//! does; [`Report::residual_evaluations`] counts only the solver's own calls.
//!
//! # Linear algebra
//! Hand-written (private module `linalg`, public module [`qr`]): Householder QR of the `m x p`
//! Jacobian, Givens re-triangularization for each `lambda`, triangular solves and, for the
//! augmented model, a Cholesky factorization. Tall Jacobians (at least
//! [`qr::TALL_QR_MIN_ROWS`] rows) use [`qr::tall_qr`], which reads `J` once in L1-sized row
//! blocks and folds each into the `p x p` triangle (the column scaling and `Q^T r` fused in), so
//! the full-data descents write no `m x p` copy of `J`; smaller ones use the in-place
//! [`qr::householder_qr`]. Not a general library, because (a) the other operations needed (QR of
//! a column subset into preallocated buffers, Givens updates of `[T; sqrt(lambda) I]`) are not
//! ones it offers, (b) at our sizes the hand-written kernels are faster: faer 0.24's
//! `qr_in_place` with a preallocated scratch (no allocation either) took about twice the CPU time
//! of [`qr::tall_qr`] at 10000 x 7 and 25 x 7 (`examples/qr_timing.rs`; faer is a
//! dev-dependency only, the reference of the differential test `tests/qr_faer.rs`), and for a
//! 13x13 Cholesky solve the shared measurement gave hand-written 0.7 us, nalgebra 0.8 us, faer
//! 1.4 us (not re-measured here), and (c) it adds no build time. The QR form (rather than `J^T J`
//! plus Cholesky, the first version) was chosen after measuring NIST: the normal-equation version
//! reached only 44/54 and stalled on the ill-conditioned Lanczos problems.
//!
//! # Test problems
//! [`problems`] holds the Moré-Garbow-Hillstrom collection ([`problems::mgh`]) and the NIST StRD
//! problems ([`problems::nist`]) as public [`Problem`]s, for tests, benchmarks and stress-test
//! crates.
//!
//! # Workspace
//! [`Solver`] owns all buffers and only grows them, so repeated solves of the same or a smaller
//! size allocate nothing (`tests/alloc.rs` proves it with a counting global allocator).
//!
//! # Measured
//! NIST StRD (27 problems x 2 starts, analytic Jacobians, default budgets): 52/54 reach LRE >= 4
//! in every parameter (PORT N2FB: 46/54; exchangeable terms such as MGH17's two exponentials may
//! come in either order); the failures are MGH17 start 1 (singular convergence, code 7, after a
//! long step onto the plateau where an exponential has died out) and MGH10 start 1 (iteration
//! limit; the evaluation limit with the second-order correction), and no success code is ever
//! returned on a wrong answer. With budgets of 5000
//! iterations and evaluations: 52/54 (the same two; PORT: 50/54). With
//! [`RadiusUpdate::Classic`]: 50/54 (MGH09 start 1, MGH10 start 1 and Bennett5 from both starts
//! stop on the iteration limit) with 1944 iterations and 2245 residual evaluations.
//! On the sls tuning instance (AED, 10 iterations per descent, 1000 seeds) the default needs
//! fewer sample-evaluations to reach the target than the classic rule: median 107,097 instead
//! of 121,326, 90th percentile 340,789 instead of 549,313.
//! Table: `results/nist-lm.md`, regenerated by
//! `cargo run -p bounded-lm --release --example nist_table`.
//!
//! Moré-Garbow-Hillstrom ([`problems::mgh`], 39 problem sizes from x0 and 10 x0, unbounded and
//! in a box that cuts off the unbounded minimiser; default budgets; `cargo run -p bounded-lm
//! --release --example mgh_table -- OUT.md [gauss-newton|adaptive|n2fb] [no-secant]`):
//!
//! | configuration | unbounded solved | boxed KKT | boxed solved or failure code | Brown-Dennis x0 / 10 x0 iterations | table |
//! |---|---|---|---|---|---|
//! | Adaptive switching after 2p updates, secant scaling after 2p updates, second-order correction (default) | 71/78 | 75/78 | 78/78 | 23 / 27 | `crates/lm/MGH.md` |
//! | The default without the second-order correction (the default before 2026-12-03) | 70/78 | 74/78 | 78/78 | 23 / 27 | `crates/lm/MGH-no-correction.md` |
//! | Gauss-Newton, secant scaling after 2p updates (with the correction; without it, the default before 2026-12-02: 70/78, 74/78) | 71/78 | 74/78 | 78/78 | 71 / 81 | `crates/lm/MGH-gauss-newton.md` |
//! | Gauss-Newton, no secant scaling, with the correction (without it, before issue 14: 66/78, 68/78, 150 (limit) / 150 (limit)) | 65/78 | 68/78 | 78/78 | 147 / 148 | `crates/lm/MGH-no-secant.md` |
//! | Adaptive switching at once, secant scaling after 2p updates, with the correction (without it: 67/78, 73/78) | 70/78, one with a success code on a wrong answer (Beale from 10 x0) | 73/78 | 78/78 | 25 / 24 | `crates/lm/MGH-adaptive.md` |
//! | Adaptive, no secant scaling, with the correction (without it: 68/78) | 69/78 | 71/78 | 77/78 | 26 / 30 | - |
//! | N2FB ([`Options::n2fb`]: Adaptive, secant scaling at once, no correction) | 69/78 | 73/78 | 78/78 | 21 / 24 | `crates/lm/MGH-n2fb.md` |
//! | The searches' descents (default with dead columns free, N2FB's singular test and no correction; `mgh_table -- OUT default free-dead n2fb-singular-test no-correction`) | 69/78 | 74/78 | 78/78 | 23 / 27 | - |
//!
//! The searches' configuration loses Chebyquad (n = 8) from 10 x0 to N2FB's singular test (code
//! 7 after 2 evaluations at f = 1.0e22).
//!
//! The box of each problem is computed from a 5000-iteration solve with a pinned configuration
//! ([`problems::mgh::box_reference_options`], the Gauss-Newton model), so it does not move
//! when the defaults change.
//! No configuration returns a success code on a wrong unbounded answer, except the adaptive
//! model switching at once with the correction: Beale from 10 x0 ends with X-convergence
//! (code 3) at f = 0.22605 on its valley to infinity (whose infimum is 0.2260), a path the
//! correction opened (the default, with the same correction, ends there at the iteration
//! limit); "77/78" marks one boxed
//! run ended by a success code short of the table's KKT test (with the previous boxes: N2FB's
//! configuration on Meyer from 10 x0, code 4 at f = 9911.756 with the projected gradient still
//! 1.7e-5 of the start's against the table's 1e-6; f has converged to RFCTOL, which is what
//! code 4 claims). The unbounded failures of the default: Beale, Jennrich and Sampson, Meyer,
//! Box 3-D, Osborne 2 and Penalty II (n = 10) from 10 x0, Gulf Research from x0 (iteration
//! limit at f = 4.1e-3; solved in 142 iterations without the second-order correction). Without
//! the correction Osborne 1 from 10 x0 and Penalty II (n = 10) from x0 fail too, and Gulf
//! Research is solved. Without the secant scaling Brown and Dennis (both starts), Penalty I (n = 4, x0) and
//! Chebyquad (n = 7, 8, 10 x0) failed too and Osborne 1 from 10 x0 was solved (in 141
//! iterations). Penalty II creeps in a curved valley (above); Box 3-D and Osborne 2 from 10 x0
//! start where exponentials have died out (numerically dead columns, code 7); Jennrich and
//! Sampson from 10 x0 needs [`Options::lift_round_off_radius`] and then ends at another
//! stationary point (code 7 at f = 129.79 after 50 iterations); Beale from 10 x0 follows a valley
//! to infinity. Traced iteration by iteration (2026-12-02), none of these is a rule of N2FB that
//! ours lacks:
//! - *Box 3-D from 10 x0*: `x2 = 100` makes its column `t e^(-100 t)` at most 4.5e-6, so
//!   `D_2 = 4.5e-6` (above the 1e-6 floor; N2FB's DD7UPD gives the same with its column max and
//!   JTOL = 1e-6) and the first step of scaled length 1 moves x2 to 5.1e4, the longer step to
//!   2.0e5, where its column is exactly zero: the rest is a fit of x1, x3 alone, code 7 at its
//!   minimum (f = 3.78e-2).
//! - *Osborne 2 from 10 x0*: the Gaussian terms `exp(-x_k (t - x_l)^2)` with `x_l` = 20 to 55
//!   and `t <= 6.4` are exactly zero at the start, so only x1 and x5 have nonzero columns; code 7
//!   at f = 0.895 is N2FB's answer for zero columns.
//! - *Penalty II (n = 10)*: the last residual `r_2n = sum (n-j+1) x_j^2 - 1` stays within
//!   2e-4 of zero, so the true second-order term `2 r_2n diag(n-j+1)` is below about 4e-3, but
//!   a step of length `delta` along the valley raises `r_2n` by about `(n-j+1) delta^2`, a
//!   quartic rise of f that neither quadratic model sees: steps of scaled length 9e-3 are
//!   rejected, 3e-3 accepted with reductions near 5e-8, and the secant `S` (diagonal swinging
//!   between -6 and +4 from one iteration to the next) does not help. That rise is what the
//!   second-order correction (above) measures at a rejected step and takes out: from x0 the
//!   default now reaches the minimum in 107 iterations (code 4); from 10 x0 it ends at the
//!   evaluation limit 3.6e-5 relative above it.
//! - *Osborne 1 from 10 x0*: from iteration 23 on the Gauss-Newton model is nearly singular
//!   (Newton step 5e3 to 3e1 scaled long, lambda about 1e-8); steps with actual/predicted
//!   0.3 to 0.9 keep RADFAC = 1 (N2FB's increase needs a reduction of 0.75 `|g^T s|`, about 1.5
//!   PREDUC here), and f falls from 3.97e-5 to 3.57e-5 in 130 iterations (f* = 2.73e-5). The
//!   model switched once (iteration 16, augmented Newton steps to a point where that model
//!   predicted 2e-10) and back. With the second-order correction (above) it is solved in 62
//!   iterations.
//!
//! Issue 14's target of 90% (71/78) is met by the default with the second-order correction
//! (71/78, 91%; 70/78 without it, and 70 or 71 for correction limits from 0.25 to none, so the
//! 71st run is at the margin; the correction's robust gain is in iterations, above). None of
//! the remaining failures is a rule of N2FB that ours lacks. Brown and Dennis takes 23
//! and 27 iterations with the default (target 30); it needs the augmented model, which the
//! Gauss-Newton default before 2026-12-02 did not use (71 and 81). A sweep of both delays
//! (secant scaling 0..3 x adaptive switching 1..3 updates per parameter) scored 68 to 71 of 78;
//! 71 came with delays that let the switch happen inside AED's 10-iteration descents, which
//! doubled AED's 90th percentile of sample-evaluations (520,683 to 1,137,329, 1000 seeds), so
//! it was not chosen, and a count picked that way from the test set would not be a fair claim.
//! MINPACK's never-decreasing scaling (`scaling_decay` 1, above) reached 71/78 too without the
//! correction (72/78 with it), at the costs listed there, and is left an option for the same
//! reason.
//!
//! ## Step model in the searches
//! PORT's N2FB always uses NL2SOL's adaptive model choice. Switching from the first update made
//! the searches slower on the paper's tuning instance (sample-evaluations to RMSE 0.11, 200
//! seeds, 5 s CPU cutoff, censored = +inf; `cargo run --release -p sls --example tuning_bench
//! -- --seeds 200 --cutoff 5 --algorithms aed,aers,rpls [--raw-exponent]`, deterministic counts,
//! measured before the secant term entered the scaling):
//!
//! | coordinates | model | AED median (reached) | AERS median | RPLS median |
//! |---|---|---|---|---|
//! | log1p n | Gauss-Newton | 96,905 (200/200) | 601,575 | 720,000 |
//! | log1p n | adaptive from the first update | 113,102 (194/200) | 913,000 | 780,000 |
//! | raw n (paper) | Gauss-Newton | 180,452 (200/200) | 1,074,375 | 4,600,000 |
//! | raw n (paper) | adaptive from the first update | 239,143 (188/200) | 1,664,700 | 5,120,000 |
//!
//! The default switches only after 2p secant updates (14 iterations for one lobe and `kd`), so
//! AED's and AERS's 10-iteration descents never switch and are unchanged bit for bit. One run,
//! 1000 seeds, 10 s cutoff, log1p n, Gauss-Newton (`--gauss-newton`) then the default, repeated
//! twice with identical counts (`tuning_bench -- --seeds 1000 --cutoff 10 --algorithms aed,rpls
//! [--gauss-newton]`):
//!
//! | model | AED median / p90 evaluations | RPLS median / p90 evaluations | RPLS mean CPU ms per trial |
//! |---|---|---|---|
//! | Gauss-Newton | 102,569 / 520,683 | 690,000 / 3,420,000 | 41.6, 38.7 |
//! | adaptive after 2p updates (default) | 102,569 / 520,683 | 710,000 / 2,870,000 | 35.4, 34.7 |
//!
//! RPLS's median rises 2.9% (within issue 14's 5% bound) while its 90th percentile falls 16%;
//! on the `cross` instance (100 seeds, 5 s cutoff, `--instance cross --algorithms rpls`) its
//! median fell from 2,690,000 to 2,450,000. `sls::TrialContext::set_step_model`,
//! `set_adaptive_delay` and `set_secant_scaling` select other configurations, for comparisons.

#![warn(missing_docs)]
// `!(a > b)` is deliberate throughout: it is true for NaN, which must count as failure.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Index loops mirror the textbook linear-algebra formulas and touch several arrays at once.
#![allow(clippy::needless_range_loop)]

mod linalg;
mod options;
mod problem;
pub mod problems;
pub mod qr;
mod solver;

pub use brdf_simd::{Kernel, KernelError};
pub use linalg::dispatch::{kernel, set_kernel};
pub use options::{Options, Outcome, RadiusUpdate, Report, SolveError, StepModel};
pub use problem::{ForwardDifference, Problem, ResidualsOnly};
pub use solver::Solver;

/// The default quadratic model: NL2SOL's adaptive choice, allowed to switch only after
/// [`Options::adaptive_delay`] secant updates per parameter (until then the solve is a
/// Gauss-Newton one, with which the sls results were measured; see the crate docs).
pub(crate) const DEFAULT_MODEL: StepModel = StepModel::Adaptive;
