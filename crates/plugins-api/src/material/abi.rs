//! The versioned C-ABI table that dynamic material plugins export, and the
//! [`export_material!`](crate::export_material) macro that generates it.
//!
//! A plugin `cdylib` exports one C function, [`ENTRY_SYMBOL_NAME`]
//! (`formsim_material_plugin_v1`), returning a pointer to a static
//! [`MaterialPluginV1`]: the name, summary and parameter schema, the number
//! of state variables per point, whether the model is isotropic, and
//! `extern "C"` functions (create, destroy, elastic constants, initial state,
//! batched update, last error). Versioning, strings, panics and the quiet
//! panic hook are those of the friction table ([`crate::abi`]); both tables
//! carry [`crate::ABI_VERSION`] as their first field.
//!
//! # The batch
//!
//! [`UpdateFn`] receives an [`AbiMaterialBatch`]: `n` points as flat arrays,
//! three values per point for the increments and stresses, `n_state` per
//! point for the state, one per point for each result. The stresses and the
//! state are updated in place.
//!
//! The shim the macro generates refuses a non-finite value among a point's
//! inputs (increment, stress, state) with [`STATUS_ERROR`] before the
//! material sees it, and catches a panic ([`STATUS_PANIC`]); either way it
//! writes the index of the failing point to `*failed_point`, and the points
//! from that one on are left as they came in.

use std::ffi::{c_char, c_void};

use super::{Elastic, PointResult};
use crate::abi::{AbiParamSpec, CreateFn, DestroyFn, LastErrorFn};
pub use crate::abi::{STATUS_ERROR, STATUS_OK, STATUS_PANIC};

/// Name of the exported entry function of ABI major version 1, NUL-terminated.
pub const ENTRY_SYMBOL: &[u8] = b"formsim_material_plugin_v1\0";

/// [`ENTRY_SYMBOL`] as text, for messages.
pub const ENTRY_SYMBOL_NAME: &str = "formsim_material_plugin_v1";

/// `n` points of one call, as flat arrays (see the [module docs](self)).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct AbiMaterialBatch {
    /// Number of points.
    pub n: usize,
    /// `3n` strain increments `[Δε_xx, Δε_yy, Δγ_xy]` (-), read.
    pub deps: *const f64,
    /// `3n` stresses `[σ_xx, σ_yy, σ_xy]` (MPa), read and written.
    pub stress: *mut f64,
    /// `n × n_state` state variables, point after point, read and written
    /// (may be null if `n_state == 0`).
    pub state: *mut f64,
    /// `n` results, written.
    pub result: *mut PointResult,
}

/// `elastic`: write the elastic constants and density of a handle to `*out`.
///
/// # Safety
/// `handle` is a live handle of this table's `create`; `out` is writable.
pub type ElasticFn = unsafe extern "C" fn(handle: *const c_void, out: *mut Elastic) -> i32;

/// `initial_state`: fill the `n_state` values at `state` for a virgin point
/// and write its flow stress (MPa) to `*flow_stress`.
///
/// # Safety
/// `handle` is live; `state` is writable for `n_state` values (may be null
/// if `n_state == 0`); `flow_stress` is writable.
pub type InitialStateFn =
    unsafe extern "C" fn(handle: *const c_void, state: *mut f64, flow_stress: *mut f64) -> i32;

/// `update`: advance the points of `*batch` by one step. Returns
/// [`STATUS_OK`], or [`STATUS_ERROR`]/[`STATUS_PANIC`] with the index of the
/// failing point in `*failed_point` and its message for `last_error`. Calls
/// with the same handle may run concurrently on several threads (on
/// different points).
///
/// # Safety
/// `handle` is live; the arrays of `*batch` are valid for their documented
/// lengths and do not overlap; `failed_point` is writable.
pub type UpdateFn = unsafe extern "C" fn(
    handle: *const c_void,
    batch: *const AbiMaterialBatch,
    failed_point: *mut usize,
) -> i32;

/// The table a version-1 material plugin exports through [`ENTRY_SYMBOL`]:
/// `extern "C" fn formsim_material_plugin_v1() -> *const MaterialPluginV1`.
/// Null function pointers are refused by the loader.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct MaterialPluginV1 {
    /// [`crate::ABI_VERSION`] the plugin was built against. Always first.
    pub abi_version: u32,
    /// Material name as typed in scenes, NUL-terminated.
    pub name: *const c_char,
    /// One-line summary, NUL-terminated.
    pub summary: *const c_char,
    /// Parameter schema, `n_params` entries, in the order `create` receives the values.
    pub params: *const AbiParamSpec,
    /// Number of entries of `params`.
    pub n_params: usize,
    /// State variables per point (at most [`super::MAX_STATE`]).
    pub n_state: usize,
    /// `1` if the response is isotropic in the plane, else `0`.
    pub isotropic: u8,
    /// As the friction table's [`CreateFn`]: the material from its values.
    pub create: Option<CreateFn>,
    /// As the friction table's [`DestroyFn`].
    pub destroy: Option<DestroyFn>,
    /// See [`ElasticFn`].
    pub elastic: Option<ElasticFn>,
    /// See [`InitialStateFn`].
    pub initial_state: Option<InitialStateFn>,
    /// See [`UpdateFn`].
    pub update: Option<UpdateFn>,
    /// As the friction table's [`LastErrorFn`].
    pub last_error: Option<LastErrorFn>,
}

/// Type of the exported entry function.
pub type EntryFn = extern "C" fn() -> *const MaterialPluginV1;

/// Generate the C-ABI table and the exported entry function
/// `formsim_material_plugin_v1` for a type implementing
/// [`UserMaterial`](crate::material::UserMaterial). Use it once per `cdylib`
/// crate, at its root:
///
/// ```ignore
/// plugins_api::export_material!(J2Voce);
/// ```
///
/// The texts are checked at compile time (no NUL byte, the name made of
/// `a-z 0-9 - _`), and so is `N_STATE ≤ MAX_STATE`.
#[macro_export]
macro_rules! export_material {
    ($material:ty) => {
        $crate::__export_plugin! {
            $material as $crate::material::abi::MaterialPluginV1,
            checked by $crate::material::abi::__private::check::<$material>(),
            /// Entry point of this formsim material plugin (ABI version 1): a
            /// pointer to its static C-ABI table.
            fn formsim_material_plugin_v1
        }
    };
}

/// Support code of [`export_material!`](crate::export_material): the
/// material's own shims; what both kinds share is in
/// [`crate::abi::__private`]. Not a stable API.
#[doc(hidden)]
pub mod __private {
    use std::ffi::c_void;

    use super::{AbiMaterialBatch, MaterialPluginV1, STATUS_ERROR, STATUS_OK, STATUS_PANIC};
    use crate::ParamSpec;
    use crate::abi::__private::{
        Export, Header, check_header, guarded, null_pointer, set_error, status,
    };
    use crate::material::{Elastic, MAX_STATE, PointResult, UserMaterial};
    use crate::table::with_header;

    /// Compile-time checks of `T` (evaluated in a `const _`).
    pub const fn check<T: UserMaterial>() {
        check_header(
            (T::NAME, T::SUMMARY, T::PARAMS),
            "UserMaterial::NAME must be non-empty and made of lowercase ASCII letters, digits, `-` and `_`",
            "UserMaterial::SUMMARY must not contain a NUL byte",
        );
        assert!(
            T::N_STATE <= MAX_STATE,
            "UserMaterial::N_STATE exceeds MAX_STATE"
        );
    }

    impl<T: UserMaterial> Export<MaterialPluginV1> for T {
        const NAME: &'static str = <T as UserMaterial>::NAME;
        const SUMMARY: &'static str = <T as UserMaterial>::SUMMARY;
        const PARAMS: &'static [ParamSpec] = <T as UserMaterial>::PARAMS;

        fn build(values: &[f64]) -> Result<Self, String> {
            T::from_values(values)
        }

        fn table(header: Header) -> MaterialPluginV1 {
            with_header!(MaterialPluginV1 {
                n_state: T::N_STATE,
                isotropic: u8::from(T::ISOTROPIC),
                elastic: Some(elastic::<T>),
                initial_state: Some(initial_state::<T>),
                update: Some(update::<T>),
            } header)
        }
    }

    /// `elastic` shim.
    ///
    /// # Safety
    /// As [`super::ElasticFn`].
    pub unsafe extern "C" fn elastic<T: UserMaterial>(
        handle: *const c_void,
        out: *mut Elastic,
    ) -> i32 {
        if handle.is_null() || out.is_null() {
            return null_pointer("elastic");
        }
        // SAFETY: live handle of `create::<T>` (host contract).
        let m = unsafe { &*handle.cast::<T>() };
        // SAFETY: `out` is non-null and writable (host contract).
        status(guarded(|| m.elastic()).map(|e| unsafe { out.write(e) }))
    }

    /// `initial_state` shim.
    ///
    /// # Safety
    /// As [`super::InitialStateFn`].
    pub unsafe extern "C" fn initial_state<T: UserMaterial>(
        handle: *const c_void,
        state: *mut f64,
        flow_stress: *mut f64,
    ) -> i32 {
        if handle.is_null() || flow_stress.is_null() || (state.is_null() && T::N_STATE > 0) {
            return null_pointer("initial_state");
        }
        // SAFETY: live handle (host contract).
        let m = unsafe { &*handle.cast::<T>() };
        let mut s = [0.0; MAX_STATE];
        let run = guarded(|| m.initial_state(&mut s[..T::N_STATE]));
        // SAFETY: `state` is writable for `N_STATE` values and `flow_stress`
        // for one (host contract).
        status(run.map(|f| unsafe {
            std::ptr::copy_nonoverlapping(s.as_ptr(), state, T::N_STATE);
            flow_stress.write(f);
        }))
    }

    /// `update` shim: point by point, refusing non-finite inputs and
    /// catching a panic.
    ///
    /// # Safety
    /// As [`super::UpdateFn`].
    pub unsafe extern "C" fn update<T: UserMaterial>(
        handle: *const c_void,
        batch: *const AbiMaterialBatch,
        failed_point: *mut usize,
    ) -> i32 {
        if handle.is_null() || batch.is_null() || failed_point.is_null() {
            return null_pointer("update");
        }
        // SAFETY: live handle, readable batch (host contract).
        let (m, b) = unsafe { (&*handle.cast::<T>(), *batch) };
        let k = T::N_STATE;
        if b.n > 0 && (b.deps.is_null() || b.stress.is_null() || b.result.is_null())
            || (k > 0 && b.n > 0 && b.state.is_null())
        {
            set_error("update: null array in the batch".into());
            return STATUS_ERROR;
        }
        // One guard for the whole batch (a panic is caught once, not
        // prepared for at every point); `at` tells which point was running.
        let at = std::cell::Cell::new(0);
        let run = guarded(|| {
            for i in 0..b.n {
                at.set(i);
                // SAFETY: the arrays hold `n` points (3, 3, `k` and 1 values
                // each) and do not overlap (host contract); `i < n`.
                let (deps, stress, state, result) = unsafe {
                    (
                        &*b.deps.add(3 * i).cast::<[f64; 3]>(),
                        &mut *b.stress.add(3 * i).cast::<[f64; 3]>(),
                        if k == 0 {
                            &mut [][..]
                        } else {
                            std::slice::from_raw_parts_mut(b.state.add(k * i), k)
                        },
                        &mut *b.result.add(i),
                    )
                };
                point(m, *deps, stress, state, result)?;
            }
            Ok(())
        });
        let status = match run {
            Ok(Ok(())) => return STATUS_OK,
            Ok(Err(reason)) => {
                set_error(reason);
                STATUS_ERROR
            }
            Err(panicked) => {
                set_error(panicked);
                STATUS_PANIC
            }
        };
        // SAFETY: non-null, writable (host contract).
        unsafe { failed_point.write(at.get()) };
        status
    }

    /// One point: refuse non-finite inputs, update on copies, write back on
    /// success (a panic unwinds to the batch's guard, the point untouched).
    fn point<T: UserMaterial>(
        m: &T,
        deps: [f64; 3],
        stress: &mut [f64; 3],
        state: &mut [f64],
        result: &mut PointResult,
    ) -> Result<(), String> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if !(finite(&deps) && finite(stress) && finite(state)) {
            return Err(format!(
                "non-finite input refused: Δε = {deps:?}, σ = {stress:?} MPa, state = {state:?}"
            ));
        }
        let mut s = *stress;
        let mut h = [0.0; MAX_STATE];
        let n = state.len();
        // Loops, not `copy_from_slice`: `n` is small and a `memmove` call
        // per point cost more than the copy.
        for (d, x) in h.iter_mut().zip(state.iter()) {
            *d = *x;
        }
        *result = m.update(deps, &mut s, &mut h[..n])?;
        *stress = s;
        for (d, x) in state.iter_mut().zip(h.iter()) {
            *d = *x;
        }
        Ok(())
    }
}
