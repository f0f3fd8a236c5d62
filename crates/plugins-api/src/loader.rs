//! Loading friction laws from shared libraries through the C-ABI table of [`crate::abi`].
//!
//! [`PluginLibrary::open`] loads a `cdylib`, finds its entry function
//! ([`ENTRY_SYMBOL_NAME`](crate::abi::ENTRY_SYMBOL_NAME)), checks the table's ABI version and contents, and
//! copies its name, summary and parameter schema into host memory.
//! [`PluginLibrary::build`] resolves user parameters against that schema and
//! asks the plugin to create a law; the result, a [`DynamicLaw`], implements
//! [`FrictionLaw`] by calling through the table and can be used anywhere a
//! built-in law can (one indirect call per `τ_c` evaluation, no allocation).
//!
//! Lifetimes: every [`DynamicLaw`] holds an `Arc` of its library, so the
//! library stays loaded until the last law built from it and the
//! [`PluginLibrary`] itself are dropped.
//!
//! Memory: [`ParamSpec`] has `&'static str` fields, so the texts of a table are
//! copied once per [`PluginLibrary::open`] into leaked host strings (a few
//! hundred bytes per opened library; not reclaimed when it is unloaded). Open a
//! library once and keep it, rather than re-opening it per step.
//!
//! Failures inside a plugin never unwind into the host: a panic or error in
//! `critical_shear` makes [`DynamicLaw::critical_shear`] return `τ_c = NaN`
//! and keeps the failure for [`FrictionLaw::take_failure`], so the return
//! mapping reports what happened (`plugin NAME panicked: MESSAGE; in
//! critical_shear at p = … MPa (PATH)`, [`FrictionError::PluginPanicked`]),
//! not a NaN it did not compute. The message can also be read with
//! [`take_last_error`] (on the failing thread, if the return mapping has not
//! taken it) or [`DynamicLaw::last_error`].

use std::cell::RefCell;
use std::path::Path;
use std::sync::{Arc, Mutex, PoisonError};

use crate::abi::{
    __private::PANIC_PREFIX, AbiCriticalShear, AbiShearInputs, CriticalShearFn, FrictionPluginV1,
    STATUS_ERROR, STATUS_OK, StickStiffnessFn,
};
use crate::dylib::{self, CreateError, Instance, PluginTable, Reported, Shared};
use crate::law::LawDescription;
use crate::{
    CriticalShear, FrictionError, FrictionLaw, ParamSpec, Params, PointNeeds, ShearInputs,
};

/// Every [`PointNeeds`] bit this version of formsim knows how to provide.
const KNOWN_NEEDS: PointNeeds = PointNeeds(
    PointNeeds::SLIDING_VELOCITY.0
        | PointNeeds::FLOW_STRESS.0
        | PointNeeds::TEMPERATURE.0
        | PointNeeds::SPIN.0
        | PointNeeds::VELOCITY_GRADIENT.0
        | PointNeeds::DEFORMATION_GRADIENT.0
        | PointNeeds::TOOL_ROTATION.0,
);

/// The last failure of a [`DynamicLaw`] call on a thread, and the law
/// (the address of its handle) it belongs to.
struct Failure {
    handle: usize,
    error: FrictionError,
}

thread_local! {
    static LAST_PLUGIN_FAILURE: RefCell<Option<Failure>> = const { RefCell::new(None) };
}

/// Take the message of the last plugin failure on this thread (a panic or
/// error inside a [`DynamicLaw`] call), if any, clearing it.
///
/// The return mapping already reports a plugin's failure in its error (it
/// takes it through [`FrictionLaw::take_failure`]); this is for callers that
/// evaluate `τ_c` themselves.
#[must_use]
pub fn take_last_error() -> Option<String> {
    LAST_PLUGIN_FAILURE.with(|f| f.borrow_mut().take().map(|f| f.error.to_string()))
}

/// The law's own part of its table, checked at load.
pub(crate) struct LawRest {
    stick_stiffness: StickStiffnessFn,
    critical_shear: CriticalShearFn,
    needs: PointNeeds,
    work_dependent: bool,
}

impl PluginTable for FrictionPluginV1 {
    type Rest = LawRest;

    fn rest(&self) -> Result<LawRest, String> {
        let stick_stiffness = dylib::function(self.stick_stiffness, "stick_stiffness")?;
        let critical_shear = dylib::function(self.critical_shear, "critical_shear")?;
        let needs = PointNeeds(self.needs);
        if !KNOWN_NEEDS.contains(needs) {
            return Err(format!(
                "the law needs point data unknown to this formsim (bits {:#x}; known: {}); update formsim",
                self.needs & !KNOWN_NEEDS.0,
                KNOWN_NEEDS
            ));
        }
        if self.work_dependent > 1 {
            return Err(format!(
                "invalid table: work_dependent = {} (must be 0 or 1)",
                self.work_dependent
            ));
        }
        Ok(LawRest {
            stick_stiffness,
            critical_shear,
            needs,
            work_dependent: self.work_dependent == 1,
        })
    }
}

impl Shared<FrictionPluginV1> {
    /// The error for a library that cannot be used, or misbehaved.
    fn error(&self, reason: String) -> FrictionError {
        FrictionError::Plugin {
            path: self.path.clone(),
            reason,
        }
    }

    /// The error for a panic in `call` with the panic's `message`.
    fn panicked(&self, call: String, message: &str) -> FrictionError {
        FrictionError::PluginPanicked {
            name: self.name.to_string(),
            path: self.path.clone(),
            call,
            message: message.to_string(),
        }
    }
}

/// A friction-law plugin loaded from a shared library.
///
/// Cheap to clone (shared handle). See the [module docs](self) for lifetimes
/// and memory.
#[derive(Clone)]
pub struct PluginLibrary {
    shared: Arc<Shared<FrictionPluginV1>>,
}

impl std::fmt::Debug for PluginLibrary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PluginLibrary")
            .field("path", &self.shared.path)
            .field("name", &self.shared.name)
            .field("abi_version", &self.shared.abi_version)
            .field("needs", &self.shared.rest.needs)
            .finish_non_exhaustive()
    }
}

impl PluginLibrary {
    /// Load the plugin at `path` and check its table.
    ///
    /// # Safety contract (why this function is not `unsafe`)
    ///
    /// Loading a shared library runs its initialisation code, and the host then
    /// calls functions whose signatures it cannot verify: a library is trusted
    /// like the formsim binary itself. `open` is safe to call on the premise
    /// that the file is either *not* a formsim plugin (detected: missing entry
    /// symbol) or a plugin built with [`export_friction_law!`](crate::export_friction_law)
    /// (or a hand-written table honouring every contract in [`crate::abi`]).
    /// Only open plugins you trust. What is checked: the file exists and loads;
    /// the entry symbol `formsim_friction_plugin_v1` exists; the table's
    /// `abi_version` equals [`ABI_VERSION`](crate::ABI_VERSION) (read before
    /// anything else); no function pointer is null; texts are UTF-8; the needs
    /// are known to this formsim; the parameter schema is consistent (ranges,
    /// defaults, unique names).
    ///
    /// A path without a directory part is read relative to the current
    /// directory, never searched on the system library path.
    ///
    /// # Errors
    /// [`FrictionError::Plugin`] naming the path and what is wrong: file not
    /// found, not a shared library, not a formsim friction plugin (symbol not
    /// found), ABI version mismatch (with the version to rebuild against), or an
    /// invalid table.
    pub fn open(path: impl AsRef<Path>) -> Result<Self, FrictionError> {
        let shared = Shared::open(path.as_ref()).map_err(|e| FrictionError::Plugin {
            path: e.path,
            reason: e.reason,
        })?;
        Ok(Self { shared })
    }

    /// Path the library was opened from, as given.
    #[must_use]
    pub fn path(&self) -> &str {
        &self.shared.path
    }

    /// ABI version of the table (equal to [`ABI_VERSION`](crate::ABI_VERSION) once opened).
    #[must_use]
    pub fn abi_version(&self) -> u32 {
        self.shared.abi_version
    }

    /// Law name as typed in scenes.
    #[must_use]
    pub fn name(&self) -> &'static str {
        self.shared.name
    }

    /// One-line summary with the formula.
    #[must_use]
    pub fn summary(&self) -> &'static str {
        self.shared.summary
    }

    /// Parameter schema, in the order the law receives the values.
    #[must_use]
    pub fn params(&self) -> &'static [ParamSpec] {
        self.shared.params
    }

    /// Point data the law reads beyond `p` and `ω`.
    #[must_use]
    pub fn needs(&self) -> PointNeeds {
        self.shared.rest.needs
    }

    /// Whether `τ_c` depends on the frictional work `ω`.
    #[must_use]
    pub fn work_dependent(&self) -> bool {
        self.shared.rest.work_dependent
    }

    /// Name, summary and schema as a [`LawDescription`], like a registry entry.
    #[must_use]
    pub fn description(&self) -> LawDescription {
        LawDescription {
            name: self.name(),
            summary: self.summary(),
            params: self.params(),
        }
    }

    /// Resolve `params` against the schema (defaults, ranges) and build the law.
    ///
    /// # Errors
    /// Parameter errors naming the parameter, unit and range; the plugin's
    /// rejection of the values ([`FrictionError::InvalidParameters`]); a panic in
    /// the plugin ([`FrictionError::Plugin`]).
    pub fn build(&self, params: &Params) -> Result<Box<dyn FrictionLaw>, FrictionError> {
        Ok(Box::new(self.build_dynamic(params)?))
    }

    /// As [`Self::build`], returning the concrete [`DynamicLaw`].
    ///
    /// # Errors
    /// As [`Self::build`].
    pub fn build_dynamic(&self, params: &Params) -> Result<DynamicLaw, FrictionError> {
        self.instantiate(&self.shared.resolve(params)?)
    }

    /// Build the law from one value per schema entry, in schema order.
    ///
    /// # Errors
    /// Wrong number of values; a value outside its range; as [`Self::build`].
    pub fn instantiate(&self, values: &[f64]) -> Result<DynamicLaw, FrictionError> {
        let shared = &self.shared;
        let instance = shared.create(values).map_err(|e| match e {
            CreateError::Values(e) => e,
            CreateError::Refused {
                status: STATUS_ERROR,
                message,
            } => FrictionError::InvalidParameters {
                component: shared.name.to_string(),
                reason: message,
            },
            CreateError::Refused { status, message } => shared.error(format!(
                "create returned unknown status {status}: {message}"
            )),
            CreateError::Panicked(message) => shared.panicked("create".into(), &message),
            CreateError::NullHandle => {
                shared.error("create reported success but returned a null handle".into())
            }
        })?;
        // SAFETY: the handle is live: just created, destroyed only by
        // `instance`'s `Drop`.
        let k_t = unsafe { (shared.rest.stick_stiffness)(instance.handle()) };
        if !(k_t.is_finite() && k_t > 0.0) {
            // Returning drops `instance`, which destroys the handle.
            return Err(if k_t.is_nan() {
                let text = shared.message("");
                if text.starts_with(PANIC_PREFIX) {
                    shared.panicked("stick_stiffness".into(), dylib::without_panic_prefix(&text))
                } else if text.is_empty() {
                    shared.error("stick_stiffness returned NaN".into())
                } else {
                    shared.error(format!("stick_stiffness returned NaN: {text}"))
                }
            } else {
                FrictionError::InvalidParameters {
                    component: shared.name.to_string(),
                    reason: format!(
                        "the law reports a stick stiffness k_t = {k_t} MPa/mm; it must be finite and > 0"
                    ),
                }
            });
        }
        Ok(DynamicLaw {
            instance,
            k_t,
            last_error: Mutex::new(None),
        })
    }
}

/// A friction law living in a plugin, called through its C-ABI table.
///
/// Implements [`FrictionLaw`]. A failure inside the plugin yields `τ_c = NaN`
/// and keeps the failure (a panic: [`FrictionError::PluginPanicked`]) for
/// [`FrictionLaw::take_failure`], through which the return mapping reports it,
/// and for [`Self::last_error`] and [`take_last_error`].
///
/// `Send` and `Sync`: the table's functions may be called concurrently with
/// one handle (the ABI contract), and the error slot is behind a `Mutex`.
pub struct DynamicLaw {
    /// The handle, destroyed when the law is dropped.
    instance: Instance<FrictionPluginV1>,
    /// `k_T`, read once at creation (immutable).
    k_t: f64,
    last_error: Mutex<Option<String>>,
}

impl DynamicLaw {
    /// The plugin's message for the most recent failure of this law (on any
    /// thread), if one happened.
    #[must_use]
    pub fn last_error(&self) -> Option<String> {
        self.last_error
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .clone()
    }

    /// Path of the library the law comes from.
    #[must_use]
    pub fn plugin_path(&self) -> &str {
        &self.instance.shared().path
    }

    /// Keep the failure of a `critical_shear` call (status `status` at
    /// pressure `p`) for [`FrictionLaw::take_failure`], [`take_last_error`]
    /// and [`Self::last_error`].
    #[cold]
    #[inline(never)]
    fn record_failure(&self, status: i32, p: f64) {
        let shared = self.instance.shared();
        let call = format!("critical_shear at p = {p} MPa");
        let error = match shared.reported(status) {
            Reported::Panicked(message) => shared.panicked(call, &message),
            Reported::Failed(text) => {
                shared.error(format!("{call} failed (status {status}): {text}"))
            }
        };
        *self
            .last_error
            .lock()
            .unwrap_or_else(PoisonError::into_inner) = Some(error.to_string());
        let failure = Failure {
            handle: self.instance.handle() as usize,
            error,
        };
        LAST_PLUGIN_FAILURE.with(|f| *f.borrow_mut() = Some(failure));
    }
}

impl std::fmt::Debug for DynamicLaw {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DynamicLaw")
            .field("name", &self.instance.shared().name)
            .field("path", &self.instance.shared().path)
            .field("k_t", &self.k_t)
            .finish_non_exhaustive()
    }
}

impl FrictionLaw for DynamicLaw {
    fn name(&self) -> &str {
        self.instance.shared().name
    }

    fn stick_stiffness(&self) -> f64 {
        self.k_t
    }

    fn needs(&self) -> PointNeeds {
        self.instance.shared().rest.needs
    }

    fn work_dependent(&self) -> bool {
        self.instance.shared().rest.work_dependent
    }

    #[inline]
    fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
        let input = AbiShearInputs::from(x);
        let mut out = AbiCriticalShear::default();
        let critical_shear = self.instance.shared().rest.critical_shear;
        // SAFETY: the handle is live (destroyed only when `instance` is
        // dropped), `input` readable, `out` writable; concurrent calls are
        // allowed by the ABI contract.
        let status = unsafe { critical_shear(self.instance.handle(), &input, &mut out) };
        if status == STATUS_OK {
            return out.into();
        }
        self.record_failure(status, x.p);
        CriticalShear {
            tau: f64::NAN,
            dtau_dp: f64::NAN,
            dtau_domega: f64::NAN,
            dtau_dspeed: f64::NAN,
            clamped: false,
        }
    }

    fn take_failure(&self) -> Option<FrictionError> {
        let handle = self.instance.handle() as usize;
        LAST_PLUGIN_FAILURE.with(|f| {
            let mut slot = f.borrow_mut();
            match slot.as_ref() {
                Some(failure) if failure.handle == handle => slot.take().map(|f| f.error),
                _ => None,
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ABI_VERSION;
    use crate::abi::AbiParamSpec;

    fn good_table() -> FrictionPluginV1 {
        *crate::abi::tests::table()
    }

    /// Validate a copy of a table without any library (the host executable
    /// holds the code of `crate::abi::tests`).
    fn check(t: &FrictionPluginV1) -> Result<Shared<FrictionPluginV1>, String> {
        // SAFETY: `t` is a whole, valid-or-deliberately-broken v1 table whose
        // pointers are null or point to the leaked test table's data.
        unsafe { Shared::from_table(t, String::new(), None) }
    }

    #[test]
    fn valid_table_is_copied() {
        let info = check(&good_table()).unwrap();
        assert_eq!(info.name, "touchy");
        assert_eq!(info.params.len(), 1);
        assert_eq!(info.params[0].name, "mu");
        assert_eq!(info.params[0].default, None);
        assert_eq!(info.rest.needs, PointNeeds::NONE);
    }

    #[test]
    fn version_mismatch_names_both_versions_and_the_crate_version() {
        let t = FrictionPluginV1 {
            abi_version: ABI_VERSION + 1,
            ..good_table()
        };
        let e = check(&t).err().unwrap();
        assert!(
            e.contains(&format!(
                "plugin ABI version {}, this formsim expects {ABI_VERSION}",
                ABI_VERSION + 1
            )) && e.contains("rebuild the plugin against plugins-api"),
            "{e}"
        );
    }

    #[test]
    fn broken_tables_are_refused_with_a_reason() {
        let e = check(&FrictionPluginV1 {
            critical_shear: None,
            ..good_table()
        })
        .err()
        .unwrap();
        assert!(e.contains("`critical_shear` is a null pointer"), "{e}");
        let e = check(&FrictionPluginV1 {
            name: std::ptr::null(),
            ..good_table()
        })
        .err()
        .unwrap();
        assert!(e.contains("law name is a null pointer"), "{e}");
        let e = check(&FrictionPluginV1 {
            needs: 1 << 20,
            ..good_table()
        })
        .err()
        .unwrap();
        assert!(
            e.contains("unknown to this formsim") && e.contains("0x100000"),
            "{e}"
        );
        let e = check(&FrictionPluginV1 {
            params: std::ptr::null(),
            ..good_table()
        })
        .err()
        .unwrap();
        assert!(e.contains("parameter array is a null pointer"), "{e}");
        let bad_default = AbiParamSpec {
            default_value: -1.0,
            has_default: 1,
            // SAFETY: the good table has one parameter.
            ..unsafe { *good_table().params }
        };
        let e = check(&FrictionPluginV1 {
            params: &bad_default,
            ..good_table()
        })
        .err()
        .unwrap();
        assert!(
            e.contains("default -1 - of parameter `mu` is outside its range >= 0"),
            "{e}"
        );
    }
}
