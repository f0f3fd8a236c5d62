//! [`PluginMaterial`]: a user material from a dynamic plugin
//! ([`plugins_api::material`]) as a [`Material`] of the element loop.
//!
//! A point's history is a [`PluginHistory`]: the plugin's state variables in
//! a fixed-size array (`MAX_STATE`, so the loop does not allocate) and the
//! plastic strain and flow stress the plugin last reported. The points of one
//! section — and, in the four-element kernels, of four elements — go to the
//! plugin in one batched call (at most [`CHUNK`] points per call).
//!
//! A failure inside the plugin (a panic, an error, a non-finite output)
//! leaves the call's points as they were (no thickness change, no
//! dissipation) and is kept for
//! [`Material::take_failure`], which the shell set asks after its element
//! loop: the run stops with the plugin's message instead of computing on.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

use plugins_api::material::loader::DynamicMaterial;
use plugins_api::material::{MAX_STATE, PointResult};

use super::{Material, PointUpdate};
use crate::ShellError;
use crate::lanes::Lanes4;

/// Most points per call to the plugin.
pub const CHUNK: usize = 32;

/// A point's state for a plugin material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PluginHistory {
    /// The plugin's state variables (the first `n_state` are used).
    pub state: [f64; MAX_STATE],
    /// Equivalent plastic strain the plugin last reported (-).
    pub plastic_strain: f64,
    /// Flow stress the plugin last reported (MPa).
    pub flow_stress: f64,
}

impl super::HistoryWords for PluginHistory {
    const WORDS: usize = MAX_STATE + 2;
    fn write_words(&self, out: &mut Vec<f64>) {
        out.extend(self.state);
        out.extend([self.plastic_strain, self.flow_stress]);
    }
    fn read_words(words: &[f64]) -> Self {
        let mut state = [0.0; MAX_STATE];
        state.copy_from_slice(&words[..MAX_STATE]);
        Self {
            state,
            plastic_strain: words[MAX_STATE],
            flow_stress: words[MAX_STATE + 1],
        }
    }
}

/// Whether a batch slot is being filled or read back.
#[derive(Clone, Copy, Debug)]
enum Io {
    Load,
    Store,
}

/// One call's points, on the stack.
#[derive(Debug)]
struct Batch {
    deps: [[f64; 3]; CHUNK],
    stress: [[f64; 3]; CHUNK],
    state: [f64; CHUNK * MAX_STATE],
    result: [PointResult; CHUNK],
}

impl Default for Batch {
    fn default() -> Self {
        Self {
            deps: [[0.0; 3]; CHUNK],
            stress: [[0.0; 3]; CHUNK],
            state: [0.0; CHUNK * MAX_STATE],
            result: [PointResult::default(); CHUNK],
        }
    }
}

thread_local! {
    /// Each thread's batch buffers (about 7 KB), filled before every call:
    /// kept between calls so that the element loop neither allocates nor
    /// clears them.
    static SCRATCH: std::cell::RefCell<Batch> = std::cell::RefCell::new(Batch::default());
}

/// The first failure of a plugin call, kept until the shell set asks.
#[derive(Debug, Default)]
struct FailureSlot {
    failed: AtomicBool,
    message: Mutex<Option<String>>,
}

/// A user material loaded from a plugin.
#[derive(Clone, Debug)]
pub struct PluginMaterial {
    m: DynamicMaterial,
    n_state: usize,
    virgin: PluginHistory,
    failure: Arc<FailureSlot>,
}

impl PluginMaterial {
    /// Wrap a material created from a plugin; asks it once for a virgin
    /// point's state.
    ///
    /// # Errors
    /// The plugin's failure in `initial_state`.
    pub fn new(m: DynamicMaterial) -> Result<Self, ShellError> {
        let n_state = m.n_state();
        let mut state = [0.0; MAX_STATE];
        let flow_stress = m
            .initial_state(&mut state[..n_state])
            .map_err(|e| ShellError::InvalidInput(e.to_string()))?;
        Ok(Self {
            m,
            n_state,
            virgin: PluginHistory {
                state,
                plastic_strain: 0.0,
                flow_stress,
            },
            failure: Arc::default(),
        })
    }

    /// The plugin material.
    pub fn plugin(&self) -> &DynamicMaterial {
        &self.m
    }

    /// Update `total` points, [`CHUNK`] per call: `io(Load, j, batch,
    /// slot)` puts point `j` into the batch's `slot`; after a successful call
    /// `io(Store, j, batch, slot)` takes it back. On failure the message is
    /// kept and the points are not stored (they stay as they were).
    fn batched(&self, total: usize, io: &mut impl FnMut(Io, usize, &mut Batch, usize)) {
        SCRATCH.with_borrow_mut(|b| {
            for start in (0..total).step_by(CHUNK) {
                let n = (total - start).min(CHUNK);
                for i in 0..n {
                    io(Io::Load, start + i, b, i);
                }
                let k = self.n_state;
                let result = self.m.update(
                    &b.deps[..n],
                    &mut b.stress[..n],
                    &mut b.state[..n * k],
                    &mut b.result[..n],
                );
                match result {
                    Ok(()) => {
                        for i in 0..n {
                            io(Io::Store, start + i, b, i);
                        }
                    }
                    Err(e) => self.record(e.to_string()),
                }
            }
        });
    }

    /// Copy `h`'s state into the batch's `slot`.
    fn load_state(&self, b: &mut Batch, slot: usize, h: &PluginHistory) {
        let k = self.n_state;
        // A loop, not `copy_from_slice`: `k` is small and a `memmove` call
        // per point cost more than the copy.
        for i in 0..k {
            b.state[slot * k + i] = h.state[i];
        }
    }

    /// Copy the batch's `slot` into `h`; its [`PointUpdate`].
    fn store_state(&self, b: &Batch, slot: usize, h: &mut PluginHistory) -> PointUpdate {
        let k = self.n_state;
        for i in 0..k {
            h.state[i] = b.state[slot * k + i];
        }
        let r = b.result[slot];
        h.plastic_strain = r.plastic_strain;
        h.flow_stress = r.flow_stress;
        PointUpdate {
            deps_zz: r.deps_zz,
            dissipation: r.dissipation,
        }
    }

    #[cold]
    fn record(&self, message: String) {
        let mut slot = self
            .failure
            .message
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        if slot.is_none() {
            *slot = Some(message);
        }
        self.failure.failed.store(true, Ordering::Release);
    }
}

impl Material for PluginMaterial {
    type History = PluginHistory;

    fn name(&self) -> &'static str {
        self.m.name()
    }
    fn density(&self) -> f64 {
        self.m.elastic().density
    }
    fn young(&self) -> f64 {
        self.m.elastic().young
    }
    fn poisson(&self) -> f64 {
        self.m.elastic().poisson
    }
    fn initial_history(&self) -> PluginHistory {
        self.virgin
    }

    fn update(
        &self,
        stress: &mut [f64; 3],
        history: &mut PluginHistory,
        deps: [f64; 3],
    ) -> PointUpdate {
        let [u] = self.update_points::<1>(
            std::array::from_mut(stress),
            std::array::from_mut(history),
            &[deps],
        );
        u
    }

    fn update_points<const N: usize>(
        &self,
        stress: &mut [[f64; 3]; N],
        history: &mut [PluginHistory; N],
        deps: &[[f64; 3]; N],
    ) -> [PointUpdate; N] {
        let mut out = [PointUpdate::default(); N];
        self.batched(N, &mut |io, j, b, slot| match io {
            Io::Load => {
                (b.deps[slot], b.stress[slot]) = (deps[j], stress[j]);
                self.load_state(b, slot, &history[j]);
            }
            Io::Store => {
                stress[j] = b.stress[slot];
                out[j] = self.store_state(b, slot, &mut history[j]);
            }
        });
        out
    }

    /// The four elements' points, element after element, in calls of
    /// [`CHUNK`] points. Inlined into the element kernel, so that the lane
    /// conversions compile with its instruction set.
    #[inline(always)]
    fn update_points_x4<L: Lanes4, const N: usize>(
        &self,
        stress: &mut [[L; 3]; N],
        history: &mut [[PluginHistory; N]; 4],
        deps: &[[L; 3]; N],
    ) -> [PointUpdate<L>; N] {
        let mut st = [[[0.0; 4]; 3]; N];
        let mut de = [[[0.0; 4]; 3]; N];
        for p in 0..N {
            for c in 0..3 {
                st[p][c] = stress[p][c].to_array();
                de[p][c] = deps[p][c].to_array();
            }
        }
        let mut dz = [[0.0; 4]; N];
        let mut dd = [[0.0; 4]; N];
        self.batched(4 * N, &mut |io, j, b, slot| {
            let (l, p) = (j / N, j % N);
            match io {
                Io::Load => {
                    for c in 0..3 {
                        b.deps[slot][c] = de[p][c][l];
                        b.stress[slot][c] = st[p][c][l];
                    }
                    self.load_state(b, slot, &history[l][p]);
                }
                Io::Store => {
                    for c in 0..3 {
                        st[p][c][l] = b.stress[slot][c];
                    }
                    let u = self.store_state(b, slot, &mut history[l][p]);
                    (dz[p][l], dd[p][l]) = (u.deps_zz, u.dissipation);
                }
            }
        });
        for p in 0..N {
            for c in 0..3 {
                stress[p][c] = L::from_array(st[p][c]);
            }
        }
        std::array::from_fn(|p| PointUpdate {
            deps_zz: L::from_array(dz[p]),
            dissipation: L::from_array(dd[p]),
        })
    }

    fn plastic_strain(&self, h: &PluginHistory) -> f64 {
        h.plastic_strain
    }
    fn flow_stress(&self, h: &PluginHistory) -> f64 {
        h.flow_stress
    }

    fn take_failure(&self) -> Option<String> {
        if !self.failure.failed.swap(false, Ordering::AcqRel) {
            return None;
        }
        self.failure
            .message
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .take()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lanes::F4;
    use crate::{Hardening, J2PlaneStress};
    use plugins_api::Params;
    use plugins_api::material::loader::MaterialLibrary;

    const K: f64 = 500.0;
    const EPS0: f64 = 0.01;

    /// j2-voce with `q = 0`, `h = K`, `σ_0 = K ε_0`: linear hardening, the
    /// same law as the built-in J2 with the two-point table below.
    fn linear_plugin() -> PluginMaterial {
        let lib = MaterialLibrary::linked::<j2_voce::J2Voce>().expect("table");
        let params = Params::new()
            .with("youngs_modulus", 200_000.0)
            .with("poissons_ratio", 0.3)
            .with("density", 7.8e-9)
            .with("sigma0", K * EPS0)
            .with("h", K);
        PluginMaterial::new(lib.build(&params).expect("material")).expect("adapter")
    }

    fn builtin() -> J2PlaneStress {
        let h = Hardening::table(&[(0.0, K * EPS0), (10.0, K * EPS0 + 10.0 * K)]).expect("table");
        J2PlaneStress::new(200_000.0, 0.3, 7.8e-9, h).expect("j2")
    }

    /// Increment `k` of a reproducible loading history (up to 4 × yield strain).
    fn increment(k: usize) -> [f64; 3] {
        let t = k as f64;
        let e = 4.0 * K * EPS0 / 200_000.0;
        [
            e * (0.7 * t).sin(),
            e * (1.3 * t + 1.0).cos(),
            1.5 * e * (0.4 * t).sin(),
        ]
    }

    /// Verification: a user material through the plugin table (the example
    /// j2-voce, linear hardening) gives the built-in J2's stresses, plastic
    /// strains, thickness strains and dissipation for the same law, to 1e-9
    /// of the yield stress, over 300 plastic and elastic increments, one
    /// point at a time and in the four-element lanes.
    #[test]
    fn plugin_j2_with_linear_hardening_matches_the_builtin_j2() {
        let (p, j) = (linear_plugin(), builtin());
        let (mut sp, mut hp) = ([0.0; 3], p.initial_history());
        let (mut sj, mut hj) = ([0.0; 3], j.initial_history());
        let mut lanes_s = [[F4::from_array([0.0; 4]); 3]; 1];
        let mut lanes_h = [[p.initial_history(); 1]; 4];
        let mut plastic = 0;
        for k in 0..300 {
            let d = increment(k);
            let up = p.update(&mut sp, &mut hp, d);
            let uj = j.update(&mut sj, &mut hj, d);
            let dl = [d.map(|c| F4::from_array([c; 4]))];
            let ul = p.update_points_x4(&mut lanes_s, &mut lanes_h, &dl);
            let tol = 1e-9 * K * EPS0;
            for c in 0..3 {
                assert!((sp[c] - sj[c]).abs() < tol, "step {k}: {sp:?} vs {sj:?}");
                let lanes = lanes_s[0][c].to_array();
                assert!(
                    lanes.iter().all(|x| x.to_bits() == sp[c].to_bits()),
                    "lanes at {k}"
                );
            }
            assert!((up.deps_zz - uj.deps_zz).abs() < 1e-12, "Δε_zz at {k}");
            assert!(
                (up.dissipation - uj.dissipation).abs() < 1e-9 * uj.dissipation.abs().max(1e-6)
            );
            assert_eq!(
                ul[0].dissipation.to_array()[3].to_bits(),
                up.dissipation.to_bits()
            );
            assert!((p.plastic_strain(&hp) - j.plastic_strain(&hj)).abs() < 1e-12);
            assert!((p.flow_stress(&hp) - j.flow_stress(&hj)).abs() < 1e-9 * K);
            plastic += usize::from(uj.dissipation > 0.0);
        }
        assert!(plastic > 50, "only {plastic} plastic steps");
        assert!(p.take_failure().is_none());
    }

    /// A failing plugin leaves the points as they were and reports once.
    #[test]
    fn a_failure_is_kept_for_the_shell_set_and_the_point_is_left_alone() {
        let p = linear_plugin();
        let (mut s, mut h) = ([1.0, 2.0, 3.0], p.initial_history());
        let u = p.update(&mut s, &mut h, [f64::NAN, 0.0, 0.0]);
        assert_eq!((s, u), ([1.0, 2.0, 3.0], PointUpdate::default()));
        let m = p.take_failure().expect("a failure");
        assert!(m.contains("non-finite input refused"), "{m}");
        assert!(p.take_failure().is_none(), "taken once");
    }
}
