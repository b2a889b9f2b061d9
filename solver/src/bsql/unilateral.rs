//! Unilateral contact: constraints that separate and re-close, with events located on the
//! BDF interpolant, plastic impact and a restart at order 1.
//!
//! # Derivation (what an open gap carries)
//! The compressive pressure of a gap is $p_n = -λ'_k/A_k + P_0$ [Paper eq. (1)], F_z = −λ'.
//! P_0 is a preload pressure carried through the contact whose static load is not in the
//! structural loads P(t): in the structure the preload's external push and the contact's
//! reaction to it cancel. A separated gap transmits nothing, p_n = 0, so its dynamic
//! multiplier is $λ'_k = P_0 A_k$ =: `lambda_dot_open[k]`: in the structure the contact
//! reaction is gone and the preload's push remains as an external force. This value is
//! continuous with the closed gap at the opening event (p_n = 0 there), so opening needs no
//! force jump, and the friction force of an open gap, μ A p_n = 0, vanishes by eq. (4). With
//! no preload (P_0 = 0) the open row is simply λ'_k = 0.
//!
//! # Reference
//! Closed constraint k: row $G_k v' = 0$ [Paper eq. (11)]. Open: row $λ'_k = λ'_{open,k}$.
//! Events (decreasing zero crossings, located by [`Bdf::locate_root`]):
//! - opening, closed k: $g_k = λ'_{open,k} − λ'_k = A_k p_n$ crosses 0 (p_n would turn tensile);
//! - closing, open k: $g_k = G_k u − G_k u(t_{open})$ crosses 0 (the relative normal
//!   displacement returns to where the gap opened: G_k u = (u_r − u_p)·n grows as it opens;
//!   a compliant row's level is c_k λ'_open,k, where its spring carries the open row's force).
//!
//! At a closing the approach velocity $G_k v^- < 0$ is removed by a plastic (frictionless)
//! impact on the closed set $a$: $\begin{bmatrix} M & G_a^T \\ G_a & 0 \end{bmatrix}
//! \begin{bmatrix} Δv \\ Λ \end{bmatrix} = \begin{bmatrix} 0 \\ −c \end{bmatrix}$ with
//! $c_k = G_k v^-$ for the rows closing now and 0 for rows already closed; $v^+ = v^- + Δv$,
//! the impulse $λ^+ = λ^- + Λ$ (Q = −Gᵀλ', so the contact impulse is −GᵀΛ) and u continuous.
//! The kinetic energy lost, $½ v^{-T} M v^- − ½ v^{+T} M v^+ ≥ 0$, is the impact dissipation
//! of the energy balance. Then y' is made consistent ([`consistent_initial_conditions`]),
//! rows that are inconsistent with the new set (a closed row in tension, an open row at zero
//! gap whose gap would close) flip once each, and the BDF restarts with a step
//! `restart_step_fraction` × the last step: at order 1 ([`Bdf::reinit`]), or at order 2 from
//! the Taylor past of the new system's solution ([`Bdf::reinit_taylor`], [`EventRestart`]).
//!
//! A compliant row ([`super::compliance`]) opens and closes at the same events; its force
//! λ' = G u/c is continuous at a closing (G u returns to c λ'_open), so it takes no part in
//! the impact (neither as a closing row nor as a closed one).
//!
//! The per-step callback sees the event time twice: the state before the event
//! (interpolated) and after it. Steps past an event are discarded; the callback never saw them.

use serde::{Deserialize, Serialize};

use super::residual::matvec;
use super::{BsqlSystem, FrictionForces};
use crate::bdf::warm::second_derivative;
use crate::bdf::{consistent_initial_conditions, Bdf, InitialConditionOptions, Status};
use crate::{Real, SolverError};

/// How the BDF restarts after an event.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EventRestart {
    /// At order 1 from (y, y') ([`Bdf::reinit`]); the order climbs back as at a start.
    Order1,
    /// At order 2 from the Taylor past of (y, y', y'') ([`Bdf::reinit_taylor`]).
    Taylor2,
}

/// Options of the event handling.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct UnilateralOptions {
    /// Width of the final root bracket as a fraction of the step that crossed (default: 1e-9).
    pub root_tol: Real,
    /// How the BDF restarts after an event (default: `order1`).
    pub restart: EventRestart,
    /// First step after an event as a fraction of the last accepted step (default: 0.1).
    pub restart_step_fraction: Real,
    /// Consistent y' after an event (default: the defaults of [`InitialConditionOptions`]).
    pub initial_conditions: InitialConditionOptions,
}

impl Default for UnilateralOptions {
    fn default() -> Self {
        Self {
            root_tol: 1e-9,
            restart: EventRestart::Order1,
            restart_step_fraction: 0.1,
            initial_conditions: InitialConditionOptions::default(),
        }
    }
}

impl UnilateralOptions {
    /// Check ranges; the error names the field.
    pub fn validate(&self) -> Result<(), SolverError> {
        let bad = |field, value: Real| SolverError::InvalidOption {
            field,
            value: value.to_string(),
            reason: "must be finite, > 0 and <= 1",
        };
        if !(self.root_tol > 0.0 && self.root_tol <= 1.0) {
            return Err(bad("root_tol", self.root_tol));
        }
        if !(self.restart_step_fraction > 0.0 && self.restart_step_fraction <= 1.0) {
            return Err(bad("restart_step_fraction", self.restart_step_fraction));
        }
        self.initial_conditions.validate()
    }
}

/// The active set: everything a restart file needs to continue across an open gap.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct UnilateralState {
    /// Constraints allowed to separate (the others stay closed, bilateral as in the paper).
    pub can_open: Vec<bool>,
    /// Open constraints.
    pub open: Vec<bool>,
    /// λ' an open constraint carries (P_0 A per gap; see the module docs).
    pub lambda_dot_open: Vec<Real>,
    /// G_k u at the opening of constraint k (its closing level; for a compliant row at most
    /// c_k λ'_open,k, where its spring force is the open row's).
    pub gap_ref: Vec<Real>,
    /// Root functions that have been positive since the last switch of their row.
    pub armed: Vec<bool>,
    /// Root functions at the last accepted step.
    pub g_prev: Vec<Real>,
}

/// Counters of the events (written to `summary.json`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct UnilateralStats {
    /// Constraints that opened (p_n reached 0).
    pub openings: u64,
    /// Constraints that closed again (gap reached 0).
    pub closings: u64,
    /// Event times (restarts of the BDF).
    pub events: u64,
    /// Rows flipped by the consistency check after an event.
    pub consistency_flips: u64,
    /// Root-function evaluations on the interpolant.
    pub root_evals: u64,
    /// Kinetic energy lost in plastic impacts.
    pub impact_dissipated: Real,
    /// Time of the first opening.
    pub first_separation_t: Option<Real>,
    /// Restarts at order 2 ([`EventRestart::Taylor2`]).
    #[serde(default)]
    pub warm_restarts: u64,
    /// Open constraints now.
    pub open_now: usize,
    /// Largest number of constraints open at once.
    pub max_open: usize,
}

/// Event handling around a [`Bdf`] for a [`BsqlSystem`] whose constraints may separate.
#[derive(Debug, Clone)]
pub struct Unilateral {
    st: UnilateralState,
    stats: UnilateralStats,
    opts: UnilateralOptions,
    g_now: Vec<Real>,
    y: Vec<Real>,
    yp: Vec<Real>,
    /// y'' after an event (the Taylor restart).
    ypp: Vec<Real>,
    /// An event crossed in the last step and not yet handled (its time, after `tout`).
    pending: bool,
}

fn gap_value<F: FrictionForces>(sys: &BsqlSystem<F>, k: usize, y: &[Real]) -> Real {
    let off = sys.n + sys.ng;
    sys.g_rows.row_dot(0, k, &y[off..off + sys.n])
}

fn gap_rate<F: FrictionForces>(sys: &BsqlSystem<F>, k: usize, v: &[Real]) -> Real {
    sys.g_rows.row_dot(0, k, &v[..sys.n])
}

/// Relative width of the band about zero in which a root function counts as "at zero": a
/// row that sits there (a gap at zero pressure: P_0 = 0 and no load yet) is armed, and a
/// crossing that starts there is an event once the function leaves the band downwards.
const ZERO_BAND: Real = 1e-12;

/// Width of the zero band of row k: ZERO_BAND × the row's scale (forces for a closed row:
/// the largest |λ'| and λ'_open, at least 1; lengths for an open row: |G u(t_open)|, at
/// least 1).
fn zero_band<F: FrictionForces>(
    sys: &BsqlSystem<F>,
    st: &UnilateralState,
    k: usize,
    yp: &[Real],
) -> Real {
    let scale = if st.open[k] {
        st.gap_ref[k].abs()
    } else {
        yp[sys.n..sys.n + sys.ng]
            .iter()
            .chain(&st.lambda_dot_open)
            .fold(0.0 as Real, |m, x| m.max(x.abs()))
    };
    ZERO_BAND * scale.max(1.0)
}

/// An armed row whose root function went from `g_prev` to `g_now` crossed: a decreasing zero
/// crossing (g_prev > 0 ≥ g_now), or one that started at zero (g_prev in the zero band,
/// g_now below it).
fn crosses(g_prev: Real, g_now: Real, band: Real) -> bool {
    g_now <= 0.0 && (g_prev > 0.0 || g_now < -band)
}

/// Root function of constraint k at (y, y').
fn root_value<F: FrictionForces>(
    sys: &BsqlSystem<F>,
    st: &UnilateralState,
    k: usize,
    y: &[Real],
    yp: &[Real],
) -> Real {
    if st.open[k] {
        gap_value(sys, k, y) - st.gap_ref[k]
    } else {
        st.lambda_dot_open[k] - yp[sys.n + k]
    }
}

impl Unilateral {
    /// All constraints closed at the start; `lambda_dot_open[k]` = P_0 A of gap k (0 without
    /// preload); `can_open` (None: all) marks the constraints that may separate. `y0`, `yp0`
    /// is the (consistent) start.
    pub fn new<F: FrictionForces>(
        sys: &mut BsqlSystem<F>,
        lambda_dot_open: Vec<Real>,
        can_open: Option<Vec<bool>>,
        y0: &[Real],
        yp0: &[Real],
        opts: UnilateralOptions,
    ) -> Result<Self, SolverError> {
        let ng = sys.ng;
        let st = UnilateralState {
            can_open: can_open.unwrap_or_else(|| vec![true; ng]),
            open: vec![false; ng],
            lambda_dot_open,
            gap_ref: vec![0.0; ng],
            armed: vec![false; ng],
            g_prev: vec![0.0; ng],
        };
        let mut me = Self::from_state(sys, st, opts)?;
        me.rearm(sys, y0, yp0, &[]);
        Ok(me)
    }

    /// Continue from a saved active set (restart); sets the system's open rows.
    pub fn from_state<F: FrictionForces>(
        sys: &mut BsqlSystem<F>,
        st: UnilateralState,
        opts: UnilateralOptions,
    ) -> Result<Self, SolverError> {
        opts.validate()?;
        let ng = sys.ng;
        for (what, l) in [
            ("can_open flags", st.can_open.len()),
            ("open flags", st.open.len()),
            ("lambda_dot_open", st.lambda_dot_open.len()),
            ("gap_ref", st.gap_ref.len()),
            ("armed flags", st.armed.len()),
            ("g_prev", st.g_prev.len()),
        ] {
            if l != ng {
                return Err(SolverError::DimensionMismatch {
                    what,
                    expected: ng,
                    got: l,
                });
            }
        }
        if let Some(k) = st.lambda_dot_open.iter().position(|x| !x.is_finite()) {
            return Err(SolverError::NonFinite {
                what: "lambda_dot_open",
                t: Real::NAN,
                index: k,
                value: st.lambda_dot_open[k],
            });
        }
        sys.open.copy_from_slice(&st.open);
        sys.lambda_dot_open.copy_from_slice(&st.lambda_dot_open);
        let len = 2 * sys.n + ng;
        let mut stats = UnilateralStats::default();
        stats.open_now = st.open.iter().filter(|&&o| o).count();
        stats.max_open = stats.open_now;
        Ok(Self {
            st,
            stats,
            opts,
            g_now: vec![0.0; ng],
            y: vec![0.0; len],
            yp: vec![0.0; len],
            ypp: vec![0.0; len],
            pending: false,
        })
    }

    /// The active set (for a restart file).
    pub fn state(&self) -> &UnilateralState {
        &self.st
    }

    /// Event counters.
    pub fn stats(&self) -> &UnilateralStats {
        &self.stats
    }

    /// Continue the counters of a run this one restarts.
    pub fn set_stats(&mut self, stats: UnilateralStats) {
        self.stats = stats;
        self.stats.open_now = self.st.open.iter().filter(|&&o| o).count();
    }

    /// Root values at (y, y') into g_prev; rows in `switched` are disarmed, others armed
    /// when positive or at zero (within the zero band: a gap at zero pressure, e.g. with
    /// P_0 = 0 before the load, opens as soon as it would turn tensile).
    fn rearm<F: FrictionForces>(
        &mut self,
        sys: &BsqlSystem<F>,
        y: &[Real],
        yp: &[Real],
        switched: &[usize],
    ) {
        for k in 0..sys.ng {
            let g = root_value(sys, &self.st, k, y, yp);
            let band = zero_band(sys, &self.st, k, yp);
            self.st.g_prev[k] = g;
            self.st.armed[k] = g > -band && !switched.contains(&k) && self.st.can_open[k];
        }
    }

    /// Integrate to `tout` like [`Bdf::step_to`], handling the events on the way.
    pub fn step_to<F, C>(
        &mut self,
        bdf: &mut Bdf,
        sys: &mut BsqlSystem<F>,
        tout: Real,
        mut on_step: C,
    ) -> Result<Status, SolverError>
    where
        F: FrictionForces,
        C: FnMut(&mut BsqlSystem<F>, Real, &[Real], &[Real]) -> Result<bool, SolverError>,
    {
        loop {
            if self.pending {
                self.pending = false;
                if !self.handle_event(bdf, sys, tout, &mut on_step)? {
                    return Ok(Status::Interrupted { t: bdf.t() });
                }
                if self.pending {
                    // Still after this output time (outputs denser than the steps).
                    return Ok(Status::Reached { t: tout });
                }
                continue;
            }
            let mut crossed = false;
            let mut user_stop = false;
            let (st, g_now) = (&mut self.st, &mut self.g_now);
            let status = bdf.step_to(sys, tout, |s, t, y, yp| {
                let mut any = false;
                for k in 0..s.ng {
                    g_now[k] = root_value(s, st, k, y, yp);
                    any |= st.armed[k] && crosses(st.g_prev[k], g_now[k], zero_band(s, st, k, yp));
                }
                if any {
                    crossed = true;
                    return Ok(false);
                }
                st.g_prev.copy_from_slice(g_now);
                for k in 0..s.ng {
                    st.armed[k] |= g_now[k] > 0.0 && st.can_open[k];
                }
                let go_on = on_step(s, t, y, yp)?;
                user_stop = !go_on;
                Ok(go_on)
            })?;
            if !crossed || user_stop {
                return Ok(status);
            }
            if !self.handle_event(bdf, sys, tout, &mut on_step)? {
                return Ok(Status::Interrupted { t: bdf.t() });
            }
            if self.pending {
                return Ok(Status::Reached { t: tout });
            }
        }
    }

    /// Locate the event in the last step, switch, impact, make consistent, restart.
    /// Returns false when the callback asked to stop. An event after `tout` is left pending
    /// with the output at `tout` interpolated.
    fn handle_event<F, C>(
        &mut self,
        bdf: &mut Bdf,
        sys: &mut BsqlSystem<F>,
        tout: Real,
        on_step: &mut C,
    ) -> Result<bool, SolverError>
    where
        F: FrictionForces,
        C: FnMut(&mut BsqlSystem<F>, Real, &[Real], &[Real]) -> Result<bool, SolverError>,
    {
        let ng = sys.ng;
        let h_used = bdf.state().h_used;
        let t_n = bdf.t();
        let t_tol = self.opts.root_tol * h_used + 100.0 * Real::EPSILON * (t_n.abs() + h_used);
        // Root functions at t_n (the step that crossed).
        bdf.interpolate(t_n, &mut self.y, &mut self.yp)?;
        for k in 0..ng {
            self.g_now[k] = root_value(sys, &self.st, k, &self.y, &self.yp);
        }
        let mut t_ev = Real::INFINITY;
        let mut times = vec![Real::INFINITY; ng];
        for k in 0..ng {
            let band = zero_band(sys, &self.st, k, &self.yp);
            if !(self.st.armed[k] && crosses(self.st.g_prev[k], self.g_now[k], band)) {
                continue;
            }
            let st = &self.st;
            let s: &BsqlSystem<F> = sys;
            let found = bdf.locate_root(
                st.g_prev[k],
                self.g_now[k],
                t_tol,
                &mut self.y,
                &mut self.yp,
                |_, y, yp| Ok(root_value(s, st, k, y, yp)),
            )?;
            self.stats.root_evals += found.evals as u64;
            times[k] = found.t;
            t_ev = t_ev.min(found.t);
        }
        if !t_ev.is_finite() {
            return Ok(true);
        }
        if t_ev > tout {
            // Output at tout first; the event is handled on the next call.
            bdf.interpolate_into_output(tout)?;
            self.pending = true;
            return Ok(true);
        }
        let switched: Vec<usize> = (0..ng).filter(|&k| times[k] <= t_ev + t_tol).collect();
        bdf.interpolate(t_ev, &mut self.y, &mut self.yp)?;
        let (mut y, mut yp) = (self.y.clone(), self.yp.clone());
        // A stop asked for here is honoured after the event (the state must stay consistent).
        let stop = !on_step(sys, t_ev, &y, &yp)?;
        self.stats.events += 1;
        let mut closing = Vec::new();
        for &k in &switched {
            self.switch(sys, k, &y, t_ev);
            if !self.st.open[k] {
                closing.push(k);
            }
        }
        if !closing.is_empty() {
            self.impact(sys, &closing, &mut y, t_ev)?;
        }
        // Consistent y', then flip rows inconsistent with the new set (each at most once).
        let mut flipped = switched.clone();
        loop {
            consistent_initial_conditions(
                sys,
                t_ev,
                &mut y,
                &mut yp,
                None,
                &self.opts.initial_conditions,
            )?;
            let scale = yp[sys.n..sys.n + ng]
                .iter()
                .chain(&self.st.lambda_dot_open)
                .fold(1.0 as Real, |m, x| m.max(x.abs()));
            let mut flip = None;
            for k in 0..ng {
                if !self.st.can_open[k] {
                    continue;
                }
                if flipped.contains(&k) && !closing.contains(&k) {
                    continue;
                }
                if flipped.contains(&k) && self.st.open[k] {
                    continue;
                }
                let g = root_value(sys, &self.st, k, &y, &yp);
                let wrong = if self.st.open[k] {
                    // At zero gap, not separating, accelerating into the face.
                    let rate = gap_rate(sys, k, &y[..sys.n]);
                    g.abs() <= 1e-12 * (1.0 + self.st.gap_ref[k].abs())
                        && rate <= 0.0
                        && gap_rate(sys, k, &yp[..sys.n]) < 0.0
                } else {
                    g < -1e-9 * scale
                };
                if wrong {
                    flip = Some(k);
                    break;
                }
            }
            match flip {
                Some(k) => {
                    self.switch(sys, k, &y, t_ev);
                    self.stats.consistency_flips += 1;
                    if !flipped.contains(&k) {
                        flipped.push(k);
                    } else {
                        // A closing row that is tensile at once: touch and leave.
                        closing.retain(|&c| c != k);
                    }
                }
                None => break,
            }
        }
        self.rearm(sys, &y, &yp, &flipped);
        let h = (self.opts.restart_step_fraction * h_used).max(t_tol);
        match self.opts.restart {
            EventRestart::Order1 => bdf.reinit(t_ev, &y, &yp, h)?,
            EventRestart::Taylor2 => {
                // y'' of the new system by a central difference over 1e-3 of the first step.
                if second_derivative(sys, t_ev, &y, &yp, 1e-3 * h, &mut self.ypp)? {
                    bdf.reinit_taylor(t_ev, &y, &yp, &self.ypp, h)?;
                    self.stats.warm_restarts += 1;
                } else {
                    bdf.reinit(t_ev, &y, &yp, h)?;
                }
            }
        }
        Ok(on_step(sys, t_ev, &y, &yp)? && !stop)
    }

    /// Flip constraint k at state y and time t.
    fn switch<F: FrictionForces>(
        &mut self,
        sys: &mut BsqlSystem<F>,
        k: usize,
        y: &[Real],
        t: Real,
    ) {
        if self.st.open[k] {
            self.st.open[k] = false;
            self.stats.closings += 1;
            self.stats.open_now -= 1;
        } else {
            self.st.open[k] = true;
            // A compliant row opens and closes where its spring force is λ'_open, at
            // G u = c λ'_open (G u at the located root differs from it by the interpolant's
            // inconsistency, and a closing above it would read as tensile); below it when the
            // root's G u is (the open row starts at zero then, as a rigid one).
            let (c, g) = (sys.compliance_of(k), gap_value(sys, k, y));
            self.st.gap_ref[k] = if c > 0.0 {
                g.min(c * self.st.lambda_dot_open[k])
            } else {
                g
            };
            self.stats.openings += 1;
            self.stats.open_now += 1;
            self.stats.max_open = self.stats.max_open.max(self.stats.open_now);
            self.stats.first_separation_t.get_or_insert(t);
        }
        sys.open[k] = self.st.open[k];
    }

    /// Plastic impact of the rows `closing` (see the module docs); updates v and λ in `y`.
    #[allow(non_snake_case)]
    fn impact<F: FrictionForces>(
        &mut self,
        sys: &BsqlSystem<F>,
        closing: &[usize],
        y: &mut [Real],
        t: Real,
    ) -> Result<(), SolverError> {
        let n = sys.n;
        // A compliant row transmits no impulse (its force is continuous at closing).
        let active: Vec<usize> = (0..sys.ng)
            .filter(|&k| !self.st.open[k] && sys.compliance_of(k) == 0.0)
            .collect();
        let c: Vec<Real> = active
            .iter()
            .map(|&k| {
                let r = gap_rate(sys, k, &y[..n]);
                if closing.contains(&k) && r < 0.0 {
                    r
                } else {
                    0.0
                }
            })
            .collect();
        if c.iter().all(|&x| x == 0.0) {
            return Ok(());
        }
        let na = active.len();
        let mut lu = crate::linalg::lu::DenseLu::new(n + na);
        for j in 0..n {
            for i in 0..n {
                lu.a[(i, j)] = sys.M[(i, j)];
            }
        }
        for (r, &k) in active.iter().enumerate() {
            for i in 0..n {
                lu.a[(i, n + r)] = sys.G[(k, i)];
                lu.a[(n + r, i)] = sys.G[(k, i)];
            }
        }
        lu.factor("plastic impact [M Gᵀ; G 0]", t)?;
        let mut rhs = vec![0.0; n + na];
        for r in 0..na {
            rhs[n + r] = -c[r];
        }
        lu.solve(&mut rhs)?;
        let mut mv = vec![0.0; n];
        matvec(sys.M.as_ref(), &y[..n], &mut mv, faer::Accum::Replace, 1.0);
        let ke_before: Real = 0.5 * y[..n].iter().zip(&mv).map(|(a, b)| a * b).sum::<Real>();
        for i in 0..n {
            y[i] += rhs[i];
        }
        for (r, &k) in active.iter().enumerate() {
            y[n + k] += rhs[n + r];
        }
        matvec(sys.M.as_ref(), &y[..n], &mut mv, faer::Accum::Replace, 1.0);
        let ke_after: Real = 0.5 * y[..n].iter().zip(&mv).map(|(a, b)| a * b).sum::<Real>();
        self.stats.impact_dissipated += ke_before - ke_after;
        Ok(())
    }
}
