//! `dae-runtime`: simulation of DAE models by discretized bounded sliding mode control.
//!
//! A model `x' = f(t, x, z), 0 = g(t, x, z)` (the [`Model`] trait, usually generated from
//! a `.dae` model by `dae!`) is realized as an ODE by making `z` a state driven by a control
//! `v = z'` that keeps the sliding variables `s_i` (combinations of the constraint
//! residual `w_i` and its derivatives) inside boundary layers `|s_i| <= eps_i`.
//!
//! # What the simulator does
//!
//! * **State.** `x` is integrated by an error-controlled embedded pair
//!   ([`Integrator::DormandPrince`], [`Integrator::BogackiShampine`]) or with a fixed
//!   step `h` ([`Integrator::Rk4`], the default of [`Settings::new`], or
//!   [`Integrator::Euler`]). `z` is held by a zero-order hold of `v`: between updates
//!   `z(t) = z_b + v (t - t_b)` exactly, also inside every stage.
//! * **Control update.** `v = J_hat^{-1}(-alpha_hat - K sgn(s))` with
//!   `J_s = diag(mu_i^(r_i-1)) J_Omega` from [`Model::jacobian_pattern`] and
//!   [`Model::jacobian`], factored once per update by the solver of
//!   [`Settings::solver`] (exact by default, `J_hat = J_s`; see *Solving with `J_s`*
//!   below); a singular `J_s` is [`SimError::SingularJacobian`] naming the dependent
//!   constraints and the time. `alpha_hat` is the cheap one from [`Model::sliding`] or
//!   the exact `alpha_hat + mu^(r-1) beta` ([`AlphaChoice`]).
//! * **When to update** ([`Policy`]): monitoring (as soon as some `|s_i|` reaches
//!   `eps_i` while moving outward, located inside the step, see below), a fixed period,
//!   or SPSM (`sat(s/eps)` and `v` recomputed at every stage, the continuous baseline,
//!   fixed steps only).
//! * **Reaching phase** ([`Reaching`]): attracting surfaces or contracting layers while
//!   the initial `s` is outside the layers; [`Settings::reaching_limit`] bounds its
//!   duration ([`SimError::ReachingTimeout`]).
//! * **A model without constraints** (`m = 0`) is an ODE: it is integrated the same way,
//!   with no control.
//!
//! # How crossings are located: the bound for any step
//!
//! With [`Crossing::Located`] (the default) a step ends where a sliding variable asks for
//! an update, whatever step the integrator (or the user) proposed:
//!
//! 1. **Dense `s`.** At both ends of a step the simulator knows `s_i` and its exact
//!    rate `s_i' = (J_s v + alpha)_i = alpha_hat_i + mu_i^(r_i-1) (J_Omega v + beta)_i`
//!    (one [`Model::jacobian`] and one [`Model::beta`] per step's end, reused by an
//!    update there; or one [`Model::omega_rate`], `beta + J_Omega v` in one pass, where
//!    the model gives it, and `J_Omega` only at the updates). The cubic Hermite through these four numbers is split at its
//!    extrema into monotone pieces; on each piece in order a layer boundary can be
//!    crossed once, so the first outward crossing of `|s_i| = eps_i` is found exactly on
//!    the cubic (Newton steps safeguarded by bisection), also when `s_i` leaves and
//!    re-enters the layer within the step. The reaching rules are events of the same
//!    kind: an outside variable that turns away from its surface (an extremum), and
//!    for contracting layers the arrival at `s_i = 0` or at the far side of `eps_i,k`.
//! 2. **True `s`.** The crossing is refined by Newton iterations on the true `s_i`
//!    (one [`Model::sliding`] per iteration) along the integrator's dense output of `x`
//!    (Dormand-Prince: its continuous extension of order 4; the others: the cubic
//!    Hermite of `x` from `f` at both ends), with `z` on its ramp, until `|s_i|` is
//!    within a quarter of the tolerance of `eps_i`. The iterations stay on the cubic's
//!    monotone piece that holds the event: a step that starts on the level (within the
//!    tolerance) has a root at its start too, and a cut there would end where it began.
//! 3. **Cut.** The step is cut there: the embedded pairs take the dense output as the
//!    new state, the fixed-step integrators integrate again from the step's start to
//!    the cut. The cubic is rebuilt on the shortened step from the exact end values;
//!    the step is accepted when its first event lies within `tol eps_i` of its end (in
//!    `s`) with nothing of the cubic further out between them, and no other variable
//!    leaves its layer within the step; otherwise it is cut again.
//! 4. **Update** at the end of the step when some `|s_i| >= (1 - tol) eps_i` moves
//!    outward by the exact `s'` (or an event says so).
//!
//! **Tolerance.** At every located crossing `|s_i| / eps_i` is within
//! `[1 - tol, 1 + tol]`, `tol` = [`CROSSING_TOL`] = 1e-3 by default. Between crossings
//! `|s_i| <= eps_i` holds up to the interpolation error of the cubic and the integration
//! error of `x` within one step. Measured against an independent fine integration
//! between the recorded samples (`runtime/tests/located.rs`: RK4 with steps from the
//! old rule `h = 0.2 eps / max k` up to 100 times it, Dormand-Prince and
//! Bogacki-Shampine at their default tolerance, on models of index 2, 3 and 4), the
//! largest `|s_i|` after reaching stays below `1.01 eps_i`, the target the tests
//! assert; in one run of the 18 cases the largest was `1.002 eps_i`, on a
//! Bogacki-Shampine run of the double pendulum (`cargo test --release -p dae-runtime
//! --test located -- --nocapture` prints every case). A layer counts as lost above
//! `(1 + bound_tol) eps_i`
//! ([`Settings::bound_tol`], [`BOUND_TOL`] = 1 %).
//!
//! Two refinements keep this cheap and safe. A step is aimed at most 1.3 times past the
//! crossing that the current `s'` predicts, so the cut falls near the step's end, where
//! the dense output is as accurate as the step, and one step usually spans a control
//! interval; a fixed step given by the user is then the longest step. A variable that
//! starts a step on its boundary and still moving outward (its gain too small for the
//! crossing condition at that update) is watched at `(1 + tol)` times its `|s|`: it
//! gets a fresh control each time it moves out by that fraction, as the step-end rule's
//! update after every step gave it, and the integration cannot stall on events at the
//! step's start. Should steps still shrink to nothing (two in a row shorter than a
//! millionth of the reference step, the fixed step or, with the embedded pairs, the
//! largest step allowed but at most the smallest `mu_i`: a variable resting on its
//! watch level with its rate lost in rounding), a progress guard takes the next step
//! whole, without locating in it, and updates at its end; its excursion is still
//! measured on the cubics, and [`Summary::unlocated_steps`] counts such steps.
//!
//! **Cost.** Per step: two [`Model::sliding`] at its end (the solution's, which is the
//! point's, and the embedded solution's, for the test of the step's error in `s`), one
//! [`Model::jacobian`] and [`Model::beta`] there (or one [`Model::omega_rate`] where the
//! model gives it), and the integrator's `f` evaluations
//! (Euler 1, RK4 4, Bogacki-Shampine 3, Dormand-Prince 6; each reuses its last stage, or
//! for Euler and RK4 the `f` at the step's end that the test needs, as the next step's
//! first, which holds across an update because `f` does not depend on `v`, but not
//! after a cut: one more `f` there). Per located crossing: a few [`Model::sliding`] evaluations along the
//! dense output, and for the fixed-step integrators one `f` for the end derivative and
//! the step integrated again to the cut, and at the cut `J_Omega` and `beta` (an update
//! usually follows). Per update: one factorisation and one solve (`J_Omega` and `beta`
//! of the step's end reused where they were evaluated, else evaluated then). Measured on the double pendulum of
//! `docs/work-precision.md` at `eps = 1e-3` with the designed gains: 7.0 `f`
//! evaluations per control update with Dormand-Prince against 33.9 with RK4 at the
//! old rule's step, position error 2.83e-3 against 2.90e-3, `max |s| = 1.0002 eps`
//! against `1.405 eps` (`cargo test --release -p dae-bench --test tension designed --
//! --nocapture`).
//!
//! **The thesis's rule** ([`Crossing::StepEnd`]) is kept to reproduce its numbers: a
//! crossing is noticed at the end of the step after which `|s_i| >= eps_i` and `s_i`
//! moved outward over the step (by the finite difference `s_i - s_i,prev`), with no
//! model call besides `sliding` per step, and `s_i` overshoots its layer by up to one
//! step of motion, `|s_i'| h` (1.1 % in the thesis scene at `h = 1e-4`, which the
//! summary therefore reports as a lost bound). Checking only `|s_i| >= eps_i` (without
//! "moving outward") would re-trigger on the step right after every update, while `s_i`
//! is still outside but already turning back, and collapse the period to one step.
//!
//! # Step control
//!
//! The embedded pairs accept a step when the RMS over the states of
//! `err_i / (atol + rtol max(|x_i|, |x_i,new|))` is at most 1, and scale the next step by
//! `0.9 err^(-1/q)` within `[0.2, 5]` (`q` = 5 for Dormand-Prince, 3 for
//! Bogacki-Shampine; no growth right after a rejection); the first step comes from the
//! sizes of `x`, `f` and one Euler step (Hairer, Norsett and Wanner, section II.4). The
//! tolerance is [`Settings::tolerance`], or `rtol = atol = 0.01 min eps_i`
//! ([`TOLERANCE_PER_EPS`]): a step's error then moves `s` by a small fraction of a
//! crossing's tolerance (at `0.1 eps` the Bogacki-Shampine runs of `located.rs` overshoot
//! to 1.05 eps between samples), and since steps are aimed at the next crossing anyway
//! a tighter tolerance costs little (thesis scene, Dormand-Prince: 7.0 `f` per update
//! at tolerances from 2e-2 to 1e-4, 10.9 at 1e-6). With constraints a step must also
//! keep its estimated error in every sliding variable, `|s_i(x) - s_i(x_hat)|` between
//! the solution and the embedded one, within [`LAYER_ERROR_PER_STEP`] `eps_i` (two
//! `sliding` calls per trial): the state's error alone does not bound `s`'s, which
//! weighs the states by `mu` and the model's derivatives. The fixed-step integrators
//! with located crossings (monitored policy) apply the same test to every step, with
//! an embedded solution of one order less built from `f` at the step's end (which is
//! the next step's first stage, so an accepted step costs no extra `f`): a step that
//! fails it is retried shorter, and the steps after it stay shorter until the error
//! allows the user's step again. The user's step is the longest; RK4 steps of 0.1 s on
//! the pendulum with a tenth of its gains went 1.45 % beyond the layer without this
//! test (`runtime/tests/located.rs`). `z` is not part of the error
//! estimate: its ramp is exact. Steps also end at [`Settings::max_step`], at the
//! targets of [`Simulator::advance_to`], and under [`Policy::Fixed`] at the update
//! times, so that the period itself is the step when the accuracy allows it. A step
//! that produces a non-finite state is retried shorter (a large step can leave the
//! model's domain where a smaller one does not) and reported ([`SimError::NonFinite`])
//! when it keeps failing; a step that falls below what the time can resolve is
//! [`SimError::StepUnderflow`] (which says where `J_s` came near singular, if it
//! did), [`Settings::max_steps`] bounds the work
//! ([`SimError::StepLimit`]), and [`Simulator::set_deadline`] the wall-clock time
//! ([`SimError::Deadline`], at a point the run goes on from).
//!
//! # Which algebraic output to trust: `z`, `z_eq`, `z*`
//!
//! * `z` itself is the held ramp: it oscillates around the algebraic solution with an
//!   amplitude set by the gains.
//! * `z_eq = z - J_s^{-1} s(x, z)`, with the `J_s` factored at the last update: the `z`
//!   that puts the state on the sliding surfaces `s = 0` (exact when `Omega` is affine
//!   in `z` and `J_Omega` has not changed since the update).
//! * `z* = z - J_Omega^{-1} Omega(t, x, z)`, with `Omega_i = w_i^(r_i - 1)` and
//!   `J_Omega` at the current state (one exact factorisation and solve per recorded
//!   sample): the `z` of the index-1 reduction `Omega = 0`, exact where `Omega` is
//!   affine in `z` (one Newton step otherwise). Its error is that of the state alone.
//!
//! **Trust `z*`.** Largest errors against exact solutions (over `t >= 0.5`,
//! Dormand-Prince at its default tolerance; `cargo test --release -p dae-runtime --test
//! exact z_star -- --nocapture` and `cargo test --release -p dae-bench --test tension
//! -- --nocapture`):
//!
//! | model | eps | `z` | `z_eq` | `z*` |
//! |---|---|---|---|---|
//! | index 4: `x1' = x2, x2' = x3, x3' = z, 0 = x1 - sin t` (`mu = 0.05`, `k = 20 eps`, exact alpha) | 1e-2 | 1.0e2 | 8.0e1 | 6.9e-15 |
//! | | 1e-3 | 1.0e1 | 7.9e0 | 8.9e-16 |
//! | | 1e-4 | 8.6e-1 | 3.2e-1 | 5.6e-17 |
//! | index 2: `x' = z - x, 0 = x - sin t` (`mu = 0.05`, `k = 2`, exact alpha) | 1e-2 | 2.1e-1 | 8.3e-3 | 4.4e-4 |
//! | | 1e-3 | 2.0e-2 | 7.1e-6 | 3.8e-7 |
//! | | 1e-4 | 2.0e-3 | 3.8e-7 | 2.0e-8 |
//! | double pendulum, link tensions at `t = 2` against the minimal-coordinate truth (`mu = 0.05`, `k = 1.5 mu^2 max abs(beta)`) | 1e-3 | 1.3e-2 | 6.2e-3 | 1.2e-3 |
//! | | 1e-4 | 3.6e-3 | 5.5e-4 | 1.0e-4 |
//! | | 1e-5 | 1.9e-4 | 5.3e-5 | 1.0e-5 |
//!
//! For the index-4 chain `Omega = z + cos t` does not depend on `x`, so `z*` is exact
//! to rounding, while `z_eq - z = -s / mu^3` amplifies the layer (issue 12 measured
//! `z_eq(3) = 1.32` against `-cos 3 = 0.990` at `eps = 1e-3`). For index 2
//! `z* - z = -w`, bounded by `eps` (T 3.10) and in practice far below. For the
//! pendulum `z*` is the tension of a rigid link at the simulated state (`w'' = 0`), so
//! its error is the state's: first order in `eps`, five to ten times below `z_eq`'s.
//!
//! # A run in pieces
//!
//! [`Simulator::start`], [`Simulator::advance_to`] any number of times, and
//! [`Simulator::finish`] (what [`Simulator::run`] does over `[t_start, t_end]`). The
//! simulator owns its model ([`Model`] is implemented for `&T`, `&mut T` and `Box<T>`):
//! between pieces [`Simulator::model_mut`] changes it (a parameter, a particle pinned
//! or released; what was cached at the current point is evaluated again before the
//! next step) and [`Simulator::request_update`] forces a control update at the current
//! time. Steps end at every piece's target; the sample there is recorded once, when
//! the run goes on (after a requested update) or finishes. A change that puts `s`
//! outside its layers after reaching is reported as a lost bound (below).
//!
//! [`Simulator::change_model`] makes such a change without a jump of `s` where `z` can
//! absorb it: a particle released or grabbed keeps its position and velocity, but its
//! acceleration, and with it each constraint's highest derivative
//! `Omega_i = w_i^(r_i - 1)`, jumps; `s_i` would jump by `mu_i^(r_i - 1)` times that, far
//! beyond a thin layer. The simulator moves `z` by `J_Omega^{-1}` of the jump (one exact
//! factorisation at the change), restarts the ramp there and updates the control before
//! the next step. On a 6 x 6 cloth at `eps = 1e-3` a release through `model_mut` reached a
//! strain of 0.17 (170 layers); through `change_model` every frame stays within the bound
//! (`bench/tests/generated_particles.rs`).
//!
//! [`Simulator::rescale_mu`] changes `mu` itself between pieces, the same way: `s` kept
//! where it was by moving `z`, the configured gains, the longest step and the grazing
//! return scaled with `mu`, and a growth refused (`Ok(false)`) where the new filter
//! `(mu d/dt + 1)^(r-1) w = s` could not keep `|w| <= eps` from the present state
//! (docs/method.md, section 2). `dae_particles::AdaptiveMu` uses it to search for the
//! cheapest `mu` during a run.
//!
//! # When the bound is not kept
//!
//! A run does not stop when a layer is left after reaching: the trace goes on to the
//! end and [`Summary::bound_loss`] ([`BoundLoss`]) records when and which constraint
//! left first, the largest `|s_i| / eps_i` with its constraint and time, every
//! constraint that left, and how many steps and how much time were spent beyond
//! `(1 + bound_tol) eps_i` (on the dense `s` with located crossings). A nearly singular
//! `J_s` is named there too: the smallest pivot of every factorisation is compared with
//! the largest value it had earlier in the run ([`LinearSolver::pivot_range`]; dense LU, sparse and tree
//! factors, Jacobi and ILU(0) have pivots, the Gauss-Seidel and CG iterations do not),
//! and a ratio below [`NEAR_SINGULAR`] (1e-3: the control `v`, and with it the drift
//! bound `M` the gains were designed for, grow by its inverse) is reported with its
//! time; the smallest ratio of every run is [`Summary::min_pivot_ratio`]. Where the
//! step control gives up ([`SimError::StepUnderflow`]) `J_s` is factored once more at
//! that point and also read from one solve (`|b| / |J_s^{-1} b|` against its largest
//! earlier value): the last update can precede the configuration that stopped the run.
//! Partial pivoting can keep a nearly singular dense `J_s`'s pivots large, so the dense
//! LU is read from that solve at every factorisation too (one `O(m^2)` solve, not
//! counted in [`SolverStats::solves`](crate::solve::SolverStats), against the factorisation's
//! `O(m^3)`): on `daec`'s taut-edge cloth its pivots kept 0.88 of their largest at
//! t = 0.0036 s while the solve read 0.013 (the sparse solver's pivots 0.016), and the
//! report of the layer lost just after said nothing of `J_s` before. When the
//! reaching phase does not finish by the end (or the settle time reaches past it) the
//! window statistics are `None`, never zeros, and [`Summary::seen_max_abs_s`],
//! [`Summary::seen_max_abs_w`] and the final [`Summary::s`], [`Summary::w`] say what the
//! run did. [`Summary::bound_held`] is the one test of a kept promise.
//!
//! # Solving with `J_s`
//!
//! Every solve with `J_s` (the simulator, the design toolkit's
//! [`approximate_inverse_gains`], the baselines of `dae-bench`) goes through one seam,
//! the [`LinearSolver`] trait, implemented by [`Solver`]: built once per pattern (the
//! symbolic analysis), [`factor`](LinearSolver::factor)ed with the values of
//! `J_Omega` and the row scaling `mu_i^(r_i-1)` at each update, then applied to any
//! number of right-hand sides. The solvers ([`SolverChoice`], `daec run --solver`):
//!
//! | choice | what | cost per update | memory |
//! |---|---|---|---|
//! | `dense` | LU with partial pivoting | `O(m^3)` | `m^2` |
//! | `sparse` | ordering + elimination tree once; multifrontal `LDL^T` for symmetric values, up-looking `LU` with diagonal pivots otherwise | `O(flops of the factor)` | `O(nnz(L))` |
//! | `tree` | elimination along a forest (chains, hair strands) | `O(m)` | `O(m)` |
//! | `jacobi` | `J_hat = diag(J_s)` | `O(m)` | `O(nnz)` |
//! | `gauss-seidel:K` | `K` forward sweeps, warm-started | `O(K nnz)` | `O(nnz)` |
//! | `cg:K` | `K` Jacobi-preconditioned CG iterations, warm-started (symmetric `J_Omega`) | `O(K nnz)` | `O(nnz)` |
//! | `ilu0` | incomplete LU without fill | `O(nnz * row length)` | `O(nnz)` |
//!
//! **How to choose.** [`SolverChoice::Auto`] (the default) stays exact: dense LU up
//! to [`DENSE_MAX`] constraints (or for a pattern denser than a quarter), the forest
//! elimination when the graph of the pattern's off-diagonal entries has no cycle, the
//! sparse solver otherwise. The sparse solver's
//! ordering is a perfect elimination ordering (maximum cardinality search) when that
//! graph is chordal, which the link graph of any particle tree is (the links at a
//! particle form a clique, two cliques share at most one link): branching hair is then
//! factored with no fill, in time linear in the entries. Other graphs (cloth) get
//! minimum degree, with its ties broken by the rule (multiple elimination in rounds, or
//! the most recently updated vertex) whose factor costs less. The sparse and tree solvers pivot on the diagonal (no row
//! exchanges): right for particle systems, where `J_Omega = -G M^-1 G^T` is negative
//! definite, and diagnosed otherwise ([`SimError::SolverFailed`] says to use `dense`
//! when a diagonal pivot vanishes on a nonsingular `J_s`). The approximate inverses
//! are never chosen automatically: they change the dynamics and need the gains of the
//! next section. Measured costs: `cargo run --release -p dae-bench --example solvers`
//! (64 x 64 cloth, 8,064 links: about 2 ms exact numbered row by row, 3 ms numbered at
//! random, 0.1–0.5 ms approximate).
//!
//! **Why our own sparse solver.** Measured on the 64 x 64 cloth (one core): faer 0.24's
//! supernodal `LL^T` factors in 2.8 ms (solve 0.17 ms) but costs 1 min 46 s of cold
//! compilation (2 min 6 s CPU); nalgebra-sparse 0.12's `CscCholesky` adds about 15 s
//! to nalgebra's cold build but has no fill-reducing ordering (50 ms per refactor on the
//! cloth in link order, a million factor entries); this module adds about 2 s to the
//! crate's build and factors in 2.5 ms (solve 0.26 ms).
//!
//! # Robustness with an approximate `J_hat` (T 3.22)
//!
//! With `E = J_s J_hat^{-1}`, `D = E K` and `gamma = alpha - E alpha_hat`, the
//! crossing condition holds for every sign pattern when each row satisfies
//! `D_ii > |gamma_i| + sum_{j != i} |D_ij| + k_i^c` (`k^c`:
//! [`Settings::crossing_margin`]). With [`Settings::check_robustness`] (on by default)
//! it is evaluated at every update in the statistics window and the failing rows are
//! counted ([`Summary::robustness_violations`], [`SolverSummary`]):
//!
//! * exact solvers (`E = I`): `k_i > |alpha_i - alpha_hat_i| + k_i^c`, exactly;
//! * `jacobi` (`E = J_s diag(J_s)^{-1}`, unit diagonal): formed row by row from the
//!   pattern in `O(nnz)`, exactly;
//! * iterations and `ilu0`: `E` is not formed. The computed `v` satisfies
//!   `J_s v = b - r` (residual `r`, one multiplication by `J_s`), so at the update
//!   `s' = (alpha - alpha_hat) - K sgn(s) - r`, and `k_i > |alpha_i - alpha_hat_i| +
//!   |r_i| + k_i^c` guarantees the crossing of row `i` for this update's sign pattern:
//!   an upper bound of what (T 3.22) asks, exact for the held `v`.
//!
//! [`Settings::raise_gains`] turns the count into a policy: each failing row's gain is
//! raised to `(1 + margin)` times its requirement before `v` is computed (the Jacobi
//! rows in passes, which converge to the least gains when the coupling's spectral
//! radius is below one, see there). A straight chain solved with `jacobi` is the case
//! in point: its `J_Omega` is only weakly diagonally dominant, so with equal gains every
//! interior row fails by equality, and raised (unequal) gains restore the condition. To
//! design for an approximation beforehand: [`approximate_inverse_gain`] (from a row's
//! dominance margin), [`approximate_inverse_gains`] (least gains for a coupling `E`,
//! e.g. [`jacobi_coupling`]).
//!
//! # Gains that follow the drift
//!
//! The sufficient gain (T 4.4) needs a bound `M_i` on the drift of `w_i^(r_i)` within an
//! interval, which a pilot run can only estimate, and a whole run then pays for its
//! worst moment. [`Settings::follow_drift`] sets the gains online instead: at every
//! update, from the drift of `s_i'` measured over the interval just ended (no model
//! evaluation), `k_i = max(k_i configured, safety * 2 sqrt(eps_i D_i))`, the gain
//! whose sweep crosses the layer before the drift turns `s_i'`. A smaller gain grazes
//! the layer instead (`s_i` turns back inside and returns to the level it left, where
//! the located crossing updates again), which also keeps it. [`Settings::graze`] makes
//! that the rule: a gain is raised only as far as `safety * D_i T / 2`, whose grazing
//! returns come `T` apart, and never above the sweeping gain. The sweeping gain gives one
//! variable alone its fewest updates, but every update resets all of them, and a raised
//! gain makes all of their next crossings sooner. On the five particle runs of `cargo
//! run --release -p dae-bench --example relaxed_design` every variant kept the layer
//! (fixed gains under four step controls, sweeping gains at safety 1 and 2, grazing
//! gains with `T = mu / 8`); the grazing gains made the fewest updates on the four
//! chains (on a heavy-end 10-link chain 76 per frame against 137 sweeping and 72
//! fixed; on a light 100-link chain 1,415 against 1,530 sweeping and 3,300 fixed), and
//! fixed gains the fewest on a cloth (92 against 149 grazing and 177 sweeping). It
//! predicts from the past intervals: a drift that grows faster than that still leaves
//! the layer, and the monitor reports it ([`Summary::bound_loss`]).
//!
//! [`Settings::ramp_against_drift`] goes one step beyond the method's zero-order hold:
//! from each update `v` ramps at the rate that cancels the drift of `s'` found there (a
//! finite difference along the flow), `z` is quadratic between updates, and intervals end
//! on the change of the drift instead (4.4x fewer updates on a light 100-link chain, 1.6x
//! more on a heavy-end one whose drift turns within an interval; `relaxed_design`).
//!
//! [`Settings::saturate_in_layer`] changes what the law asks of a variable found inside
//! its layer at an update: `s_i' = -k_i s_i / eps_i` (the saturation `sat(s_i / eps_i)`)
//! instead of `-k_i sgn(s_i)`. On and outside the boundary the two agree, so a located
//! crossing still turns the variable inward at the full gain and the layer is kept the
//! same way; inside it, a variable near the middle moves slowly instead of being sent
//! across at the full gain. With many constraints this is what sets the count: every
//! update resets all of them, and with `sgn` the next interval ends at the first of
//! many full-gain sweeps, whichever variable happened to start it near its boundary.
//! On the five particle runs of `relaxed_design` it made 1.5-2.0x fewer updates per
//! frame with `v` held (on a light 100-link chain 825 against 1,504) and 1.1-3.2x
//! fewer with `v` ramped (on a heavy-end 100-link chain 88 against 282), every run
//! keeping its layer; the particle benchmark's frame-tied design uses it. The method's
//! crossing period (T 3.14) assumes the full gain inside the layer and no longer bounds
//! the interval from below; the designs that rely on it (the pilot-based ones) keep
//! `sgn`.
//!
//! **Which constraints set the cost.** Every update of the monitoring policy is asked
//! for by some `s_i` at its layer boundary moving outward, and then updates all rows;
//! [`Summary::triggered_updates`] (and [`Simulator::triggered_updates`] during a run)
//! counts, per constraint, the updates it asked for. On the particle benchmark's cloth
//! (C3 (a), two far corners pinned, the far edge nearly taut) 36 of the 480 links of a
//! 16 x 16 cloth asked for the 305 updates of its first 0.2 s (`dae-bench` test
//! `on_a_nearly_taut_cloth_a_few_links_ask_for_every_update_and_each_update_factors_once`);
//! on the 32 x 32 cloth they are links hanging from the far edge (docs/particles-log.md).
//!
//! **`z` and `z_eq` with an approximate inverse.** `z` is still the held ramp: it
//! oscillates around the algebraic solution `z*` with an amplitude set by the gains, so
//! raised gains widen it (`z*` itself is always computed with an exact solver). `z_eq = z - J_hat^{-1} s` is one quasi-Newton step towards the
//! `z` on `s = 0`: for `Omega` affine in `z`, `z_eq - z* = (I - J_hat^{-1} J_s)(z - z*)`,
//! so it improves on `z` only as far as `J_hat` is good (`|I - J_hat^{-1} J_s| < 1`;
//! for `jacobi` on a weakly dominant chain barely). The iterative solvers warm-start
//! each `z_eq` solve from the previous correction, so along a run their `z_eq`
//! accumulates iterations while `s` changes slowly. Where the algebraic outputs matter,
//! record with an exact solver or more iterations.
//!
//! # Recording
//!
//! Samples go to a [`Sink`]: a [`Trace`] in memory, a [`CsvSink`] that streams, either
//! wrapped in [`Decimate`] to keep every k-th step or a minimum time spacing, two of them
//! at once with [`Tee`] (an `Option` of a sink is a sink that may be absent). Update
//! times are always recorded. A sample is a step's end: with error-controlled steps
//! about one per control interval (limit [`Settings::max_step`] for a denser trace).
//! Each recorded sample costs one solve for `z_eq` and one factorisation of `J_Omega`
//! for `z*`; a sink that reads neither says so ([`Sink::algebraic_outputs`]). A failed
//! run leaves the sink with everything up to the failure.
//!
//! # Example
//!
//! ```
//! use dae_runtime::{Model, Settings, Simulator, Trace};
//!
//! /// x' = z - x, 0 = x - sin t (index 2): exact x = sin t, z = sin t + cos t.
//! struct Tracking;
//! impl Model for Tracking {
//!     fn name(&self) -> &str { "tracking" }
//!     fn n_states(&self) -> usize { 1 }
//!     fn n_constraints(&self) -> usize { 1 }
//!     fn n_params(&self) -> usize { 0 }
//!     fn state_name(&self, _: usize) -> &str { "x" }
//!     fn alg_name(&self, _: usize) -> &str { "z" }
//!     fn constraint_name(&self, _: usize) -> &str { "track" }
//!     fn param_name(&self, _: usize) -> &str { "" }
//!     fn indices(&self) -> &[usize] { &[2] }
//!     fn param(&self, _: usize) -> f64 { 0.0 }
//!     fn set_param(&mut self, _: usize, _: f64) {}
//!     fn initial_state(&self, x: &mut [f64]) { x[0] = 0.0 }
//!     fn initial_alg(&self, z: &mut [f64]) { z[0] = 1.0 }
//!     fn rhs(&self, _: f64, x: &[f64], z: &[f64], dx: &mut [f64]) { dx[0] = z[0] - x[0] }
//!     fn sliding(&self, t: f64, x: &[f64], z: &[f64], mu: &[f64],
//!                w: &mut [f64], s: &mut [f64], ah: &mut [f64]) {
//!         w[0] = x[0] - t.sin();
//!         w[1] = z[0] - x[0] - t.cos();
//!         s[0] = mu[0] * w[1] + w[0];
//!         ah[0] = w[1];
//!     }
//!     fn jacobian_pattern(&self) -> &[(usize, usize)] { &[(0, 0)] }
//!     fn jacobian(&self, _: f64, _: &[f64], _: &[f64], j: &mut [f64]) { j[0] = 1.0 }
//!     fn beta(&self, t: f64, x: &[f64], z: &[f64], b: &mut [f64]) {
//!         b[0] = -(z[0] - x[0]) + t.sin();
//!     }
//! }
//!
//! let settings = Settings::new(vec![1e-3], vec![0.05], vec![0.1]).step(1e-3).t_end(2.0);
//! let mut trace = Trace::new();
//! let summary = Simulator::new(&Tracking, settings)?.run(&mut trace)?;
//! let t = summary.t_end;
//! assert!((summary.x[0] - t.sin()).abs() < 2e-3);
//! assert!((summary.z_eq[0] - (t.sin() + t.cos())).abs() < 0.05);
//! # Ok::<(), dae_runtime::SimError>(())
//! ```
#![warn(missing_docs)]

#[cfg(feature = "macros")]
pub use dae_macros::{dae, dae_file};

#[cfg(feature = "plot")]
pub mod charts;
pub mod design;
pub mod error;
#[cfg(feature = "families")]
pub mod family;
pub mod model;
pub mod settings;
mod sim;
pub mod solve;
pub mod summary;
pub mod trace;

/// `dae-lang` for the code that `dae-codegen` generates for family models (it builds the
/// model's `Construction` from literals). Not an API of this crate.
#[cfg(feature = "families")]
#[doc(hidden)]
pub use dae_lang as __dae_lang;

pub use error::SimError;
pub use model::Model;
pub use settings::Settings;
pub use sim::Simulator;
pub use summary::Summary;
pub use trace::Trace;
