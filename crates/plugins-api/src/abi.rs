//! The versioned C-ABI table that dynamic friction-law plugins export, and the
//! [`export_friction_law!`](crate::export_friction_law) macro that generates it.
//!
//! # Why a C table
//!
//! Rust has no stable ABI: a `Box<dyn FrictionLaw>` built by one compiler (or one
//! version of this crate) cannot be used safely by another. So a plugin `cdylib`
//! exports one C function, [`ENTRY_SYMBOL`] (`formsim_friction_plugin_v1`), that
//! returns a pointer to a static [`FrictionPluginV1`]: plain `#[repr(C)]` data
//! (name, summary, parameter schema, declared needs) and `extern "C"` function
//! pointers (create, destroy, stick stiffness, critical shear, last error).
//! The law object itself stays on the plugin side behind an opaque handle.
//!
//! # Versioning
//!
//! Two checks, both done by [`crate::loader::PluginLibrary::open`]:
//! - the symbol name carries the major version (`…_v1`); a plugin built for
//!   another major version exports another symbol;
//! - the table's first field, `abi_version`, must equal [`crate::ABI_VERSION`].
//!   `abi_version` is the first field of every version of the table, so a host
//!   can read it before it trusts the rest of the layout.
//!
//! Any change to a `#[repr(C)]` type of this module, to the meaning of a field or
//! to the calling contract of a function pointer bumps [`crate::ABI_VERSION`].
//!
//! # Panics and errors
//!
//! Unwinding across `extern "C"` aborts the process. Every shim that the macro
//! generates runs the plugin code inside [`std::panic::catch_unwind`], turns a
//! panic into [`STATUS_PANIC`] and keeps its message in a thread-local slot that
//! the host reads through [`FrictionPluginV1::last_error`] on the same thread.
//! A plugin must therefore be built with `panic = "unwind"` (Cargo's default);
//! under `panic = "abort"` a panicking plugin takes the host down with it.
//!
//! A plugin links its own copy of `std`, with its own panic hook, whose default
//! prints every panic to standard error: a law that panics at every contact
//! point of every step would flood the terminal. So the first call of the
//! entry function installs, once, a hook in the plugin's `std` that stays
//! silent for a panic inside a shim (it records where the panic happened, for
//! the message) and hands every other panic (a thread the plugin spawned
//! itself, say) to the hook that was there before. The host's own panics go
//! through the host's `std` and are not affected. The cost on the hot path is
//! one thread-local flag set and reset per call.
//!
//! The text of a caught panic, in `last_error` and in `create`'s error
//! buffer, is `panicked: MESSAGE (at FILE:LINE:COLUMN)`; the host reports it
//! once, as `plugin NAME panicked: MESSAGE …` with the call it came from.
//!
//! # Strings
//!
//! [`PluginLaw`] texts are ordinary `&'static str` consts. The macro checks at
//! compile time that they contain no NUL byte (and that the name is a scene
//! key: lowercase ASCII letters, digits, `-`, `_`), and the first call of the
//! entry function copies them once into NUL-terminated C strings that are
//! leaked for the life of the process (a few hundred bytes per plugin; the
//! table is built once and cached in a `OnceLock`).

use std::ffi::{c_char, c_void};

use crate::{CriticalShear, FrictionLaw, ParamSpec, PointNeeds, ShearInputs};

/// Name of the exported entry function of ABI major version 1, NUL-terminated.
pub const ENTRY_SYMBOL: &[u8] = b"formsim_friction_plugin_v1\0";

/// [`ENTRY_SYMBOL`] as text, for messages.
pub const ENTRY_SYMBOL_NAME: &str = "formsim_friction_plugin_v1";

/// Return status of a table function: success.
pub const STATUS_OK: i32 = 0;
/// Return status of a table function: the plugin reported an error (bad
/// values, null pointer); the text is in the error buffer or [`FrictionPluginV1::last_error`].
pub const STATUS_ERROR: i32 = 1;
/// Return status of a table function: the plugin code panicked; the panic
/// message is available through [`FrictionPluginV1::last_error`].
pub const STATUS_PANIC: i32 = 2;

/// [`ShearInputs`] across the C boundary (same fields, same units).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AbiShearInputs {
    /// Contact pressure `p ≥ 0` (MPa).
    pub p: f64,
    /// Frictional work density `ω ≥ 0` (N/mm).
    pub omega: f64,
    /// Sliding speed (mm/s); NaN unless the law needs it.
    pub sliding_speed: f64,
    /// Blank flow stress (MPa); NaN unless the law needs it.
    pub flow_stress: f64,
    /// Temperature (K); NaN unless the law needs it.
    pub temperature: f64,
}

impl From<&ShearInputs> for AbiShearInputs {
    #[inline]
    fn from(x: &ShearInputs) -> Self {
        Self {
            p: x.p,
            omega: x.omega,
            sliding_speed: x.sliding_speed,
            flow_stress: x.flow_stress,
            temperature: x.temperature,
        }
    }
}

impl From<&AbiShearInputs> for ShearInputs {
    #[inline]
    fn from(x: &AbiShearInputs) -> Self {
        Self {
            p: x.p,
            omega: x.omega,
            sliding_speed: x.sliding_speed,
            flow_stress: x.flow_stress,
            temperature: x.temperature,
        }
    }
}

/// [`CriticalShear`] across the C boundary; `clamped` is `0` or `1`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AbiCriticalShear {
    /// Critical shear stress `τ_c` (MPa).
    pub tau: f64,
    /// `∂τ_c/∂p` (-).
    pub dtau_dp: f64,
    /// `∂τ_c/∂ω` (1/mm).
    pub dtau_domega: f64,
    /// `∂τ_c/∂|v|` (MPa·s/mm).
    pub dtau_dspeed: f64,
    /// `1` if a lower clamp of the law is active, else `0`.
    pub clamped: u8,
}

impl From<CriticalShear> for AbiCriticalShear {
    #[inline]
    fn from(c: CriticalShear) -> Self {
        Self {
            tau: c.tau,
            dtau_dp: c.dtau_dp,
            dtau_domega: c.dtau_domega,
            dtau_dspeed: c.dtau_dspeed,
            clamped: u8::from(c.clamped),
        }
    }
}

impl From<AbiCriticalShear> for CriticalShear {
    #[inline]
    fn from(c: AbiCriticalShear) -> Self {
        Self {
            tau: c.tau,
            dtau_dp: c.dtau_dp,
            dtau_domega: c.dtau_domega,
            dtau_dspeed: c.dtau_dspeed,
            clamped: c.clamped != 0,
        }
    }
}

/// One [`ParamSpec`] across the C boundary. Strings are NUL-terminated UTF-8
/// and live as long as the library stays loaded.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct AbiParamSpec {
    /// Key as typed in scenes.
    pub name: *const c_char,
    /// Unit (`-` if dimensionless).
    pub unit: *const c_char,
    /// One-line description.
    pub doc: *const c_char,
    /// Default value; meaningful only if `has_default != 0`.
    pub default_value: f64,
    /// `1` if the parameter has a default, `0` if it is required.
    pub has_default: u8,
    /// Lower bound.
    pub min: f64,
    /// `1` if the lower bound is excluded (`> min`).
    pub min_exclusive: u8,
    /// Upper bound (inclusive), `+∞` for none.
    pub max: f64,
}

/// `create`: build a law from `n` parameter values (in schema order, already
/// resolved and range-checked by the host). On success writes an opaque handle
/// to `*out_handle` and returns [`STATUS_OK`]; otherwise writes a NUL-terminated
/// message (truncated to `err_len` bytes) to `err_buf` and returns
/// [`STATUS_ERROR`] or [`STATUS_PANIC`].
///
/// # Safety
/// `values` is readable for `n` values (may be null if `n == 0`); `out_handle`
/// is writable; `err_buf` is null or writable for `err_len` bytes.
pub type CreateFn = unsafe extern "C" fn(
    values: *const f64,
    n: usize,
    out_handle: *mut *mut c_void,
    err_buf: *mut c_char,
    err_len: usize,
) -> i32;

/// `destroy`: free a handle made by `create`.
///
/// # Safety
/// `handle` comes from this table's `create`, is destroyed exactly once and
/// not used afterwards (may be called from any thread).
pub type DestroyFn = unsafe extern "C" fn(handle: *mut c_void);

/// `stick_stiffness`: `k_T` (MPa/mm) of a handle; NaN if the plugin failed.
///
/// # Safety
/// `handle` is a live handle from this table's `create`.
pub type StickStiffnessFn = unsafe extern "C" fn(handle: *const c_void) -> f64;

/// `critical_shear`: evaluate `τ_c` and its derivatives into `*out`; returns
/// [`STATUS_OK`], or [`STATUS_PANIC`]/[`STATUS_ERROR`] with `*out` unspecified.
/// The plugin must allow concurrent calls from several threads with the same
/// handle.
///
/// # Safety
/// `handle` is a live handle from this table's `create`; `x` is readable and
/// `out` writable.
pub type CriticalShearFn = unsafe extern "C" fn(
    handle: *const c_void,
    x: *const AbiShearInputs,
    out: *mut AbiCriticalShear,
) -> i32;

/// `last_error`: copy the message of the last failure on the calling thread
/// into `buf` (at most `len - 1` bytes, cut at a UTF-8 boundary, then a NUL)
/// and return the full length of the message in bytes (0: no message). With
/// `len == 0` or a null `buf` only the length is returned.
///
/// # Safety
/// `buf` is null or writable for `len` bytes.
pub type LastErrorFn = unsafe extern "C" fn(buf: *mut c_char, len: usize) -> usize;

/// The table a version-1 plugin exports through [`ENTRY_SYMBOL`]:
/// `extern "C" fn formsim_friction_plugin_v1() -> *const FrictionPluginV1`.
///
/// The function pointers are `Option`s, which have the layout of a plain
/// (nullable) C function pointer; the loader rejects a table with a null one.
/// They are `unsafe` to call: the pointers they take must honour the contract
/// stated on each type (`unsafe` is not part of the C calling convention, so a
/// plugin written in C exports the same table).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct FrictionPluginV1 {
    /// [`crate::ABI_VERSION`] of the `plugins-api` the plugin was built
    /// against. Always the first field.
    pub abi_version: u32,
    /// Law name as typed in scenes, NUL-terminated.
    pub name: *const c_char,
    /// One-line summary with the formula, NUL-terminated.
    pub summary: *const c_char,
    /// Parameter schema, `n_params` entries, in the order `create` receives the values.
    pub params: *const AbiParamSpec,
    /// Number of entries of `params`.
    pub n_params: usize,
    /// [`PointNeeds`] bits: point data the law reads beyond `p` and `ω`.
    pub needs: u32,
    /// `1` if `τ_c` depends on the frictional work `ω`, else `0`.
    pub work_dependent: u8,
    /// See [`CreateFn`].
    pub create: Option<CreateFn>,
    /// See [`DestroyFn`].
    pub destroy: Option<DestroyFn>,
    /// See [`StickStiffnessFn`].
    pub stick_stiffness: Option<StickStiffnessFn>,
    /// See [`CriticalShearFn`].
    pub critical_shear: Option<CriticalShearFn>,
    /// See [`LastErrorFn`].
    pub last_error: Option<LastErrorFn>,
}

/// Type of the exported entry function.
pub type EntryFn = extern "C" fn() -> *const FrictionPluginV1;

/// What a law type adds to its [`FrictionLaw`] impl to be exported as a
/// dynamic plugin with [`export_friction_law!`](crate::export_friction_law).
///
/// `NEEDS` and `WORK_DEPENDENT` are part of the static table (the host reads
/// them before any law exists); `create` checks that a built law's
/// [`FrictionLaw::needs`] and [`FrictionLaw::work_dependent`] agree with them.
pub trait PluginLaw: FrictionLaw + Sized + 'static {
    /// Name as typed in scenes: lowercase ASCII letters, digits, `-`, `_`.
    const NAME: &'static str;
    /// One-line summary with the formula.
    const SUMMARY: &'static str;
    /// Parameter schema; `from_values` receives the values in this order.
    const PARAMS: &'static [ParamSpec];
    /// Point data the law reads beyond `p` and `ω`.
    const NEEDS: PointNeeds = PointNeeds::NONE;
    /// Whether `τ_c` depends on `ω`.
    const WORK_DEPENDENT: bool = false;

    /// Build the law from one value per entry of [`Self::PARAMS`], already
    /// range-checked by the host. Return `Err` for invalid combinations.
    ///
    /// # Errors
    /// A one-line reason naming the parameters involved.
    fn from_values(values: &[f64]) -> Result<Self, String>;
}

/// Generate the C-ABI table and the exported entry function
/// `formsim_friction_plugin_v1` for a type implementing
/// [`FrictionLaw`] and [`PluginLaw`](crate::abi::PluginLaw).
///
/// Use it once per `cdylib` crate, at its root:
///
/// ```ignore
/// plugins_api::export_friction_law!(ExpDecay);
/// ```
///
/// The texts of `PluginLaw` are checked at compile time (no NUL byte, name made
/// of `a-z 0-9 - _`).
#[macro_export]
macro_rules! export_friction_law {
    ($law:ty) => {
        $crate::__export_plugin! {
            $law as $crate::abi::FrictionPluginV1,
            checked by $crate::abi::__private::check_texts::<$law>(),
            /// Entry point of this formsim friction plugin (ABI version 1): a
            /// pointer to its static C-ABI table.
            fn formsim_friction_plugin_v1
        }
    };
}

/// What [`export_friction_law!`](crate::export_friction_law) and
/// [`export_material!`](crate::export_material) generate: the compile-time
/// check of the type and the entry function `$symbol`, which builds the
/// table of type `$table` once and returns it. Not a stable API.
#[doc(hidden)]
#[macro_export]
macro_rules! __export_plugin {
    (
        $ty:ty as $table:ty,
        checked by $check:expr,
        $(#[$attr:meta])*
        fn $symbol:ident
    ) => {
        const _: () = $check;

        $(#[$attr])*
        #[unsafe(no_mangle)]
        pub extern "C" fn $symbol() -> *const $table {
            static TABLE: ::std::sync::OnceLock<$crate::abi::__private::Leaked<$table>> =
                ::std::sync::OnceLock::new();
            $crate::abi::__private::entry::<$table, $ty>(&TABLE)
        }
    };
}

/// Support code of [`export_friction_law!`](crate::export_friction_law) and
/// [`export_material!`](crate::export_material); not a stable API.
///
/// What both kinds share lives here: the panic guard and the error slot of
/// `last_error`, the table's header (texts, schema, `create`, `destroy`,
/// `last_error`) and the entry function, through
/// [`Export`](__private::Export). The shims of a law's or a material's own
/// functions live with their kind.
#[doc(hidden)]
pub mod __private {
    use std::any::Any;
    use std::cell::{Cell, RefCell};
    use std::ffi::{CString, c_char, c_void};
    use std::panic::{AssertUnwindSafe, catch_unwind};
    use std::sync::{Once, OnceLock};

    use super::{
        AbiCriticalShear, AbiParamSpec, AbiShearInputs, FrictionPluginV1, PluginLaw, STATUS_ERROR,
        STATUS_OK, STATUS_PANIC,
    };
    pub use crate::table::Header;
    use crate::table::with_header;
    use crate::{ParamSpec, ShearInputs};

    thread_local! {
        static LAST_ERROR: RefCell<String> = const { RefCell::new(String::new()) };
        /// Whether this thread is running plugin code inside a shim, where a
        /// panic is caught and reported through `last_error`, not printed.
        static IN_SHIM: Cell<bool> = const { Cell::new(false) };
        /// Where the last panic caught in a shim happened (`file:line:column`).
        static PANIC_AT: RefCell<Option<String>> = const { RefCell::new(None) };
    }

    /// The prefix of a caught panic's text in `last_error`.
    pub const PANIC_PREFIX: &str = "panicked: ";

    /// Install, once per copy of `std`, the panic hook described in the
    /// [module docs](super): silent inside a shim, the previous hook elsewhere.
    pub fn install_quiet_hook() {
        static INSTALLED: Once = Once::new();
        INSTALLED.call_once(|| {
            let previous = std::panic::take_hook();
            std::panic::set_hook(Box::new(move |info| {
                // `try_with`: a hook must not panic, even while the thread's
                // locals are being torn down.
                if IN_SHIM.try_with(Cell::get).unwrap_or(false) {
                    let at = info
                        .location()
                        .map(|l| format!("{}:{}:{}", l.file(), l.line(), l.column()));
                    let _ = PANIC_AT.try_with(|p| p.replace(at));
                } else {
                    previous(info);
                }
            }));
        });
    }

    /// Run plugin code: its value, or the text of its panic
    /// (`panicked: MESSAGE (at FILE:LINE:COLUMN)`), caught without printing.
    pub fn guarded<R>(f: impl FnOnce() -> R) -> Result<R, String> {
        IN_SHIM.with(|in_shim| {
            let outer = in_shim.replace(true);
            let result = catch_unwind(AssertUnwindSafe(f));
            in_shim.set(outer);
            result.map_err(|payload| {
                let message = panic_text(payload);
                match PANIC_AT.with(|p| p.borrow_mut().take()) {
                    Some(at) => format!("{PANIC_PREFIX}{message} (at {at})"),
                    None => format!("{PANIC_PREFIX}{message}"),
                }
            })
        })
    }

    /// What a type exported as a plugin whose table is `Tab` gives the shared
    /// code: the texts and schema of the header, how to build a value behind
    /// a handle, and the rest of the table. Implemented for every
    /// [`PluginLaw`] (`Tab` = [`FrictionPluginV1`]) and every
    /// [`UserMaterial`](crate::material::UserMaterial) (`Tab` =
    /// [`MaterialPluginV1`](crate::material::abi::MaterialPluginV1)).
    pub trait Export<Tab>: Send + Sync + Sized + 'static {
        /// Name as typed in scenes.
        const NAME: &'static str;
        /// One-line summary.
        const SUMMARY: &'static str;
        /// Parameter schema, in the order [`Self::build`] receives the values.
        const PARAMS: &'static [ParamSpec];

        /// The value behind a new handle, from one value per entry of
        /// [`Self::PARAMS`].
        ///
        /// # Errors
        /// The plugin's reason to refuse the values.
        fn build(values: &[f64]) -> Result<Self, String>;

        /// The whole table: `header` and the kind's own fields.
        fn table(header: Header) -> Tab;
    }

    impl<T: PluginLaw> Export<FrictionPluginV1> for T {
        const NAME: &'static str = <T as PluginLaw>::NAME;
        const SUMMARY: &'static str = <T as PluginLaw>::SUMMARY;
        const PARAMS: &'static [ParamSpec] = <T as PluginLaw>::PARAMS;

        fn build(values: &[f64]) -> Result<Self, String> {
            let law = T::from_values(values)?;
            if law.needs() != T::NEEDS || law.work_dependent() != T::WORK_DEPENDENT {
                return Err(format!(
                    "needs()/work_dependent() of the built law ({}, {}) disagree with PluginLaw::NEEDS/WORK_DEPENDENT ({}, {})",
                    law.needs(),
                    law.work_dependent(),
                    T::NEEDS,
                    T::WORK_DEPENDENT
                ));
            }
            Ok(law)
        }

        fn table(header: Header) -> FrictionPluginV1 {
            with_header!(FrictionPluginV1 {
                needs: T::NEEDS.0,
                work_dependent: u8::from(T::WORK_DEPENDENT),
                stick_stiffness: Some(stick_stiffness::<T>),
                critical_shear: Some(critical_shear::<T>),
            } header)
        }
    }

    /// A leaked, immutable table that may live in a `static`.
    pub struct Leaked<Tab: 'static>(pub &'static Tab);

    // SAFETY: a table and everything it points to (leaked C strings, leaked
    // parameter array, function pointers) is immutable after construction and
    // lives for the rest of the process, so sharing it between threads is sound.
    unsafe impl<Tab> Sync for Leaked<Tab> {}
    // SAFETY: as for `Sync`: immutable 'static data.
    unsafe impl<Tab> Send for Leaked<Tab> {}

    /// Whether `s` has no NUL byte (and, for a name, is a non-empty scene key).
    pub const fn text_ok(s: &str, is_name: bool) -> bool {
        let b = s.as_bytes();
        if is_name && b.is_empty() {
            return false;
        }
        let mut i = 0;
        while i < b.len() {
            let c = b[i];
            if c == 0 {
                return false;
            }
            if is_name && !(c.is_ascii_lowercase() || c.is_ascii_digit() || c == b'-' || c == b'_')
            {
                return false;
            }
            i += 1;
        }
        true
    }

    /// Compile-time check of the texts of `T` (evaluated in a `const _`).
    pub const fn check_texts<T: PluginLaw>() {
        check_header(
            (T::NAME, T::SUMMARY, T::PARAMS),
            "PluginLaw::NAME must be non-empty and made of lowercase ASCII letters, digits, `-` and `_`",
            "PluginLaw::SUMMARY must not contain a NUL byte",
        );
    }

    /// Compile-time check of a header's texts (`name`, `summary`, `params`):
    /// stops the build with `name_rule` or `summary_rule` if one is broken.
    pub const fn check_header(
        (name, summary, params): (&str, &str, &[ParamSpec]),
        name_rule: &str,
        summary_rule: &str,
    ) {
        if !text_ok(name, true) {
            panic!("{}", name_rule);
        }
        if !text_ok(summary, false) {
            panic!("{}", summary_rule);
        }
        let mut i = 0;
        while i < params.len() {
            let p = &params[i];
            assert!(
                text_ok(p.name, true),
                "parameter names must be non-empty and made of lowercase ASCII letters, digits, `-` and `_`"
            );
            assert!(
                text_ok(p.unit, false) && text_ok(p.doc, false),
                "parameter units and docs must not contain a NUL byte"
            );
            i += 1;
        }
    }

    /// `s` as a NUL-terminated C string leaked for the life of the process.
    pub fn leak_c(s: &str) -> Option<*const c_char> {
        let c = CString::new(s).ok()?;
        Some(Box::leak(c.into_boxed_c_str()).as_ptr())
    }

    /// A parameter schema as C structs, leaked (texts as leaked C strings).
    pub fn abi_params(specs: &[ParamSpec]) -> Option<&'static [AbiParamSpec]> {
        let mut params = Vec::with_capacity(specs.len());
        for p in specs {
            params.push(AbiParamSpec {
                name: leak_c(p.name)?,
                unit: leak_c(p.unit)?,
                doc: leak_c(p.doc)?,
                default_value: p.default.unwrap_or(f64::NAN),
                has_default: u8::from(p.default.is_some()),
                min: p.min,
                min_exclusive: u8::from(p.min_exclusive),
                max: p.max,
            });
        }
        Some(Box::leak(params.into_boxed_slice()))
    }

    /// The table of `T`, leaked; `None` if a text holds a NUL byte.
    fn build_table<Tab: 'static, T: Export<Tab>>() -> Option<Leaked<Tab>> {
        let params = abi_params(T::PARAMS)?;
        let header = Header {
            abi_version: crate::ABI_VERSION,
            name: leak_c(T::NAME)?,
            summary: leak_c(T::SUMMARY)?,
            params: params.as_ptr(),
            n_params: params.len(),
            create: Some(create::<Tab, T>),
            destroy: Some(destroy::<T>),
            last_error: Some(last_error),
        };
        Some(Leaked(Box::leak(Box::new(T::table(header)))))
    }

    /// Body of the exported entry function: the table of `T`, built once;
    /// null if building it failed (texts are checked at compile time, so
    /// only on allocation failure or a panic), with the reason for
    /// `last_error`.
    pub fn entry<Tab: 'static, T: Export<Tab>>(cell: &'static OnceLock<Leaked<Tab>>) -> *const Tab {
        // Nothing may unwind out of here; installing a hook only panics on a
        // thread that is already panicking, and then the default hook stays.
        let _ = catch_unwind(install_quiet_hook);
        let built = guarded(|| {
            if let Some(t) = cell.get() {
                return Some(t.0 as *const Tab);
            }
            let table = build_table::<Tab, T>()?;
            Some(cell.get_or_init(|| table).0 as *const Tab)
        });
        match built {
            Ok(Some(ptr)) => ptr,
            Ok(None) => {
                set_error("could not build the plugin table (a text contains a NUL byte)".into());
                std::ptr::null()
            }
            Err(panicked) => {
                set_error(format!("{panicked} (while building the plugin table)"));
                std::ptr::null()
            }
        }
    }

    /// Keep `message` for the `last_error` of this thread.
    pub fn set_error(message: String) {
        LAST_ERROR.with(|e| *e.borrow_mut() = message);
    }

    /// [`STATUS_ERROR`], with `CALL: null pointer from the host` kept for
    /// `last_error`: what a shim returns when the host breaks its contract.
    #[cold]
    pub fn null_pointer(call: &str) -> i32 {
        set_error(format!("{call}: null pointer from the host"));
        STATUS_ERROR
    }

    /// The status of a shim whose plugin code ran under [`guarded`]:
    /// [`STATUS_OK`], or [`STATUS_PANIC`] with the panic's text kept for
    /// `last_error`.
    #[inline]
    pub fn status(run: Result<(), String>) -> i32 {
        match run {
            Ok(()) => STATUS_OK,
            Err(panicked) => {
                set_error(panicked);
                STATUS_PANIC
            }
        }
    }

    /// The message of a panic payload; drops the payload without letting a
    /// panicking `Drop` escape.
    fn panic_text(payload: Box<dyn Any + Send>) -> String {
        let text = if let Some(s) = payload.downcast_ref::<&str>() {
            (*s).to_string()
        } else if let Some(s) = payload.downcast_ref::<String>() {
            s.clone()
        } else {
            "panic with a non-text payload".to_string()
        };
        if let Err(inner) = catch_unwind(AssertUnwindSafe(move || drop(payload))) {
            std::mem::forget(inner);
        }
        text
    }

    /// Copy `message` into `buf` (at most `len - 1` bytes, cut at a char
    /// boundary, NUL-terminated). Returns the full length of `message`.
    ///
    /// # Safety
    /// `buf` is null or writable for `len` bytes.
    pub unsafe fn copy_out(message: &str, buf: *mut c_char, len: usize) -> usize {
        if !buf.is_null() && len > 0 {
            let mut n = message.len().min(len - 1);
            while !message.is_char_boundary(n) {
                n -= 1;
            }
            // SAFETY: `buf` is writable for `len` bytes (function contract) and
            // `n + 1 <= len`; `message` is Rust-owned and cannot overlap it.
            unsafe {
                std::ptr::copy_nonoverlapping(message.as_ptr().cast::<c_char>(), buf, n);
                buf.add(n).write(0);
            }
        }
        message.len()
    }

    /// `create` shim of either kind: the host's pointers and the count
    /// checked, [`Export::build`] run on the values under the guard, the
    /// handle written or the failure's text copied out.
    ///
    /// # Safety
    /// As [`super::CreateFn`].
    pub unsafe extern "C" fn create<Tab, T: Export<Tab>>(
        values: *const f64,
        n: usize,
        out_handle: *mut *mut c_void,
        err_buf: *mut c_char,
        err_len: usize,
    ) -> i32 {
        let fail = |status: i32, message: String| {
            // SAFETY: the host passes an `err_buf` writable for `err_len` bytes, or null.
            unsafe { copy_out(&message, err_buf, err_len) };
            set_error(message);
            status
        };
        if out_handle.is_null() || (values.is_null() && n > 0) {
            return fail(STATUS_ERROR, "create: null pointer from the host".into());
        }
        let expected = T::PARAMS.len();
        if n != expected {
            return fail(
                STATUS_ERROR,
                format!("create: {n} parameter values given, the schema has {expected}"),
            );
        }
        let built = guarded(|| {
            let values: &[f64] = if n == 0 {
                &[]
            } else {
                // SAFETY: the host passes `n` readable values (checked non-null above).
                unsafe { std::slice::from_raw_parts(values, n) }
            };
            T::build(values).map(|value| Box::into_raw(Box::new(value)).cast::<c_void>())
        });
        match built {
            Ok(Ok(handle)) => {
                // SAFETY: `out_handle` is non-null and points to writable storage (host contract).
                unsafe { out_handle.write(handle) };
                STATUS_OK
            }
            Ok(Err(reason)) => fail(STATUS_ERROR, reason),
            Err(panicked) => fail(STATUS_PANIC, panicked),
        }
    }

    /// `destroy` shim.
    ///
    /// # Safety
    /// As [`super::DestroyFn`].
    pub unsafe extern "C" fn destroy<T: 'static>(handle: *mut c_void) {
        if handle.is_null() {
            return;
        }
        // SAFETY: `handle` was made by a `create` shim from `Box<T>` and the
        // host destroys it exactly once.
        let value = unsafe { Box::from_raw(handle.cast::<T>()) };
        if let Err(panicked) = guarded(move || drop(value)) {
            set_error(format!("{panicked} (in drop)"));
        }
    }

    /// `stick_stiffness` shim: NaN on panic, with the panic's text for
    /// `last_error`; the slot is cleared first, so that a NaN without a text
    /// is the law's own value, not an older failure.
    ///
    /// # Safety
    /// As [`super::StickStiffnessFn`].
    pub unsafe extern "C" fn stick_stiffness<T: PluginLaw>(handle: *const c_void) -> f64 {
        set_error(String::new());
        if handle.is_null() {
            set_error("stick_stiffness: null handle".into());
            return f64::NAN;
        }
        // SAFETY: `handle` was made by `create::<T>` and is live (host contract).
        let law = unsafe { &*handle.cast::<T>() };
        match guarded(|| law.stick_stiffness()) {
            Ok(k) => k,
            Err(panicked) => {
                set_error(panicked);
                f64::NAN
            }
        }
    }

    /// `critical_shear` shim: [`STATUS_PANIC`] on panic, message kept for `last_error`.
    ///
    /// # Safety
    /// As [`super::CriticalShearFn`].
    pub unsafe extern "C" fn critical_shear<T: PluginLaw>(
        handle: *const c_void,
        x: *const AbiShearInputs,
        out: *mut AbiCriticalShear,
    ) -> i32 {
        if handle.is_null() || x.is_null() || out.is_null() {
            return null_pointer("critical_shear");
        }
        // SAFETY: `handle` was made by `create::<T>` and is live; `x` points to a
        // valid `AbiShearInputs` (host contract, non-null checked above).
        let (law, inputs) = unsafe { (&*handle.cast::<T>(), ShearInputs::from(&*x)) };
        // The law is only borrowed immutably: a panic cannot leave it half-updated.
        let run = guarded(|| law.critical_shear(&inputs));
        // SAFETY: `out` is non-null and writable (host contract).
        status(run.map(|cs| unsafe { out.write(AbiCriticalShear::from(cs)) }))
    }

    /// `last_error` shim.
    ///
    /// # Safety
    /// As [`super::LastErrorFn`].
    pub unsafe extern "C" fn last_error(buf: *mut c_char, len: usize) -> usize {
        // SAFETY: the host passes a `buf` writable for `len` bytes, or null.
        catch_unwind(|| LAST_ERROR.with(|e| unsafe { copy_out(&e.borrow(), buf, len) }))
            .unwrap_or(0)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use std::ffi::{CStr, c_char, c_void};

    use super::*;

    /// A law that panics above a pressure: exercises the shims in-process.
    struct Touchy {
        mu: f64,
    }

    impl FrictionLaw for Touchy {
        fn name(&self) -> &str {
            Self::NAME
        }
        fn stick_stiffness(&self) -> f64 {
            1e5
        }
        fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
            assert!(x.p <= 100.0, "touchy law refuses p = {}", x.p);
            CriticalShear {
                tau: self.mu * x.p,
                dtau_dp: self.mu,
                ..CriticalShear::default()
            }
        }
    }

    impl PluginLaw for Touchy {
        const NAME: &'static str = "touchy";
        const SUMMARY: &'static str = "τ_c = μ p, panics above 100 MPa";
        const PARAMS: &'static [ParamSpec] = &[ParamSpec::required(
            "mu",
            "-",
            0.0,
            f64::INFINITY,
            "friction coefficient",
        )];
        fn from_values(values: &[f64]) -> Result<Self, String> {
            if values[0] > 5.0 {
                return Err(format!("mu = {} is implausible", values[0]));
            }
            Ok(Self { mu: values[0] })
        }
    }

    crate::export_friction_law!(Touchy);

    /// The table of the in-crate test plugin `touchy`.
    pub(crate) fn table() -> &'static FrictionPluginV1 {
        let ptr = formsim_friction_plugin_v1();
        assert!(!ptr.is_null());
        // SAFETY: the generated entry returns a leaked 'static table.
        unsafe { &*ptr }
    }

    fn last_error_text() -> String {
        let mut buf = [0 as c_char; 256];
        // SAFETY: `buf` is writable for its length.
        let n = unsafe { (table().last_error.unwrap())(buf.as_mut_ptr(), buf.len()) };
        // SAFETY: `last_error` NUL-terminates within the buffer.
        let s = unsafe { CStr::from_ptr(buf.as_ptr()) }
            .to_string_lossy()
            .into_owned();
        assert_eq!(n, s.len());
        s
    }

    #[test]
    fn table_carries_version_texts_and_schema() {
        let t = table();
        assert_eq!(t.abi_version, crate::ABI_VERSION);
        // SAFETY: the table's strings are leaked NUL-terminated C strings.
        let name = unsafe { CStr::from_ptr(t.name) }.to_str().unwrap();
        assert_eq!(name, "touchy");
        assert_eq!(t.n_params, 1);
        // SAFETY: `params` holds `n_params` entries.
        let p = unsafe { &*t.params };
        assert_eq!(unsafe { CStr::from_ptr(p.name) }.to_str().unwrap(), "mu");
        assert_eq!(p.has_default, 0);
        // Same table on every call.
        assert!(std::ptr::eq(t, table()));
    }

    #[test]
    fn shims_evaluate_catch_panics_and_report_errors() {
        let t = table();
        let (create, shear) = (t.create.unwrap(), t.critical_shear.unwrap());
        let mut handle: *mut c_void = std::ptr::null_mut();
        let mut err = [0 as c_char; 64];
        // SAFETY (all calls below): valid value arrays, writable out-pointers and
        // buffers of the stated lengths; `handle` is live until `destroy`.
        let status = unsafe { create([9.0].as_ptr(), 1, &mut handle, err.as_mut_ptr(), err.len()) };
        assert_eq!(status, STATUS_ERROR);
        // SAFETY: `create` NUL-terminates its error buffer.
        let text = unsafe { CStr::from_ptr(err.as_ptr()) }.to_str().unwrap();
        assert!(text.contains("implausible"), "{text}");

        let status = unsafe { create([0.2].as_ptr(), 1, &mut handle, err.as_mut_ptr(), err.len()) };
        assert_eq!(status, STATUS_OK);
        let mut out = AbiCriticalShear::default();
        let x = AbiShearInputs {
            p: 10.0,
            omega: 0.0,
            sliding_speed: f64::NAN,
            flow_stress: f64::NAN,
            temperature: f64::NAN,
        };
        assert_eq!(unsafe { shear(handle, &x, &mut out) }, STATUS_OK);
        assert_eq!(out.tau, 0.2 * 10.0);
        let x = AbiShearInputs { p: 1000.0, ..x };
        assert_eq!(unsafe { shear(handle, &x, &mut out) }, STATUS_PANIC);
        let text = last_error_text();
        assert!(
            text.starts_with("panicked: touchy law refuses p = 1000 (at ")
                && text.contains("abi.rs:"),
            "{text}"
        );
        // Still usable after the panic.
        assert_eq!(unsafe { (t.stick_stiffness.unwrap())(handle) }, 1e5);
        unsafe { (t.destroy.unwrap())(handle) };
    }

    #[test]
    fn error_copy_truncates_at_a_char_boundary_and_reports_full_length() {
        let mut buf = [0 as c_char; 4];
        // SAFETY: `buf` is writable for its length.
        let n = unsafe { __private::copy_out("αβγ", buf.as_mut_ptr(), buf.len()) };
        assert_eq!(n, "αβγ".len());
        // SAFETY: NUL-terminated by `copy_out`.
        let s = unsafe { CStr::from_ptr(buf.as_ptr()) }.to_str().unwrap();
        assert_eq!(s, "α");
        // SAFETY: a null buffer is allowed.
        assert_eq!(
            unsafe { __private::copy_out("abc", std::ptr::null_mut(), 0) },
            3
        );
    }
}
