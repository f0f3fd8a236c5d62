//! What every kind of dynamic plugin shares on the host side: opening the
//! shared library, finding a versioned entry symbol, reading the table's
//! texts and parameter schema, and reading the plugin's last error message.
//!
//! The friction-law loader ([`crate::loader`]) and the user-material loader
//! ([`crate::material::loader`]) are both written on these functions and on
//! [`Shared`] and [`Instance`] (a loaded table, a live handle), so a plugin
//! of either kind is opened, checked, created, destroyed and reported the
//! same way.

use std::ffi::{CStr, c_char, c_void};
use std::path::{Path, PathBuf};

use libloading::Library;

use crate::ParamSpec;
use crate::abi::{AbiParamSpec, LastErrorFn};
use crate::table::HasHeader;

mod loaded;

pub(crate) use loaded::{
    CreateError, Instance, PluginTable, Reported, Shared, without_panic_prefix,
};

/// Upper bound on a plugin's parameter count, to reject corrupt tables.
pub(crate) const MAX_PARAMS: usize = 256;

/// Size of the host buffers that receive plugin error messages (bytes).
pub(crate) const ERROR_BUFFER: usize = 1024;

/// Load the shared library at `path` after checking that it is a readable
/// file. A path without a directory part is read relative to the current
/// directory, never searched on the system library path.
///
/// # Errors
/// File not found, a directory, not valid UTF-8, not loadable.
pub(crate) fn open_library(path: &Path) -> Result<Library, String> {
    // A device, FIFO or directory is refused before the loader opens it.
    crate::input_file::check(path, crate::input_file::MESH_LIMIT).map_err(|e| e.to_string())?;
    let mut load_path = PathBuf::from(path);
    if path.parent().is_none_or(|p| p.as_os_str().is_empty()) {
        load_path = Path::new(".").join(path);
    }
    let load_text = load_path
        .to_str()
        .ok_or_else(|| "the path is not valid UTF-8".to_string())?
        .to_string();
    // SAFETY: loading runs the library's initialisers; the loaders document
    // that a plugin is trusted like the formsim binary itself.
    unsafe { Library::new(load_text) }
        .map_err(|e| format!("cannot be loaded as a shared library: {e}"))
}

/// Open the library at `path`, find the entry function
/// `formsim_{KIND}_plugin_v1` of the table kind `Tab` and call it: the
/// library and the table it returns (non-null).
///
/// # Errors
/// As [`open_library`]; the symbol missing (with the reason of
/// [`missing_entry_reason`]); a null table.
pub(crate) fn load_table<Tab: HasHeader>(path: &Path) -> Result<(Library, *const Tab), String> {
    let library = open_library(path)?;
    let (kind, prefix) = (Tab::KIND, format!("formsim_{}_plugin_v", Tab::KIND));
    let symbol = format!("{prefix}1");
    // SAFETY: the entry symbol has type `extern "C" fn() -> *const Tab` in
    // every library that defines it (the ABI v1 contract of that kind); the
    // pointer is only called while `library` is alive (the caller keeps it).
    let entry: Option<extern "C" fn() -> *const Tab> =
        unsafe { library.get::<extern "C" fn() -> *const Tab>(symbol.as_bytes()) }
            .ok()
            .map(|s| *s);
    let Some(entry) = entry else {
        return Err(missing_entry_reason(&library, kind, &prefix));
    };
    let table = entry();
    if table.is_null() {
        return Err(format!(
            "`{symbol}` returned no table (the plugin failed to build it)"
        ));
    }
    Ok((library, table))
}

/// Why a library without the `{prefix}1` entry symbol is refused (`kind`:
/// `friction`, `material`); mentions another major version's symbol, or the
/// other kind's, if the library exports one.
pub(crate) fn missing_entry_reason(library: &Library, kind: &str, prefix: &str) -> String {
    let mut reason =
        format!("this library is not a formsim {kind} plugin: symbol `{prefix}1` not found");
    for major in (0..=16u32).filter(|&m| m != 1) {
        let symbol = format!("{prefix}{major}");
        if exports(library, &symbol) {
            reason.push_str(&format!(
                " (it exports `{symbol}`: plugin ABI major version {major}, this formsim expects {}: \
                 rebuild the plugin against plugins-api {})",
                crate::ABI_VERSION,
                env!("CARGO_PKG_VERSION")
            ));
            return reason;
        }
    }
    for (other, symbol) in [
        ("friction", crate::abi::ENTRY_SYMBOL_NAME),
        ("material", crate::material::abi::ENTRY_SYMBOL_NAME),
    ] {
        if other != kind && exports(library, symbol) {
            reason.push_str(&format!(" (it is a {other} plugin: it exports `{symbol}`)"));
        }
    }
    reason
}

/// The kinds of dynamic plugin formsim loads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PluginKind {
    /// A friction law (`formsim_friction_plugin_v1`, [`crate::loader`]).
    Friction,
    /// A user material (`formsim_material_plugin_v1`, [`crate::material::loader`]).
    Material,
}

/// Which kind of plugin the library at `path` is, by the version-1 entry
/// symbol it exports; `None` if it cannot be loaded or exports neither (the
/// kind's own loader then says why).
pub fn plugin_kind(path: &Path) -> Option<PluginKind> {
    let library = open_library(path).ok()?;
    if exports(&library, crate::material::abi::ENTRY_SYMBOL_NAME) {
        Some(PluginKind::Material)
    } else if exports(&library, crate::abi::ENTRY_SYMBOL_NAME) {
        Some(PluginKind::Friction)
    } else {
        None
    }
}

/// Whether `library` exports `symbol`.
pub(crate) fn exports(library: &Library, symbol: &str) -> bool {
    // SAFETY: only the presence of the symbol is tested; it is never called
    // or dereferenced, so its type does not matter.
    unsafe { library.get::<*const c_void>(symbol.as_bytes()) }.is_ok()
}

/// The function `what` of a table, refused if it is a null pointer.
pub(crate) fn function<F>(f: Option<F>, what: &str) -> Result<F, String> {
    f.ok_or_else(|| format!("invalid table: function `{what}` is a null pointer"))
}

/// The message for a table whose `abi_version` is not ours.
pub(crate) fn version_mismatch(found: u32) -> String {
    format!(
        "plugin ABI version {found}, this formsim expects {}: rebuild the plugin against plugins-api {}",
        crate::ABI_VERSION,
        env!("CARGO_PKG_VERSION")
    )
}

/// Copy a NUL-terminated UTF-8 text of a table.
///
/// # Safety
/// `ptr` is null or points to a NUL-terminated string.
pub(crate) unsafe fn text(ptr: *const c_char, what: &str) -> Result<String, String> {
    if ptr.is_null() {
        return Err(format!("invalid table: {what} is a null pointer"));
    }
    // SAFETY: non-null and NUL-terminated (function contract).
    let c = unsafe { CStr::from_ptr(ptr) };
    c.to_str()
        .map(str::to_string)
        .map_err(|_| format!("invalid table: {what} is not valid UTF-8"))
}

/// A host string that lives for the rest of the process.
pub(crate) fn leak(s: String) -> &'static str {
    Box::leak(s.into_boxed_str())
}

/// Whether `name` is a scene key: non-empty, `a-z 0-9 - _`.
pub(crate) fn is_key(name: &str) -> bool {
    !name.is_empty()
        && name
            .bytes()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == b'-' || c == b'_')
}

/// Read, check and copy a table's parameter schema (`n` entries at `ptr`).
///
/// # Safety
/// `ptr` is null or points to `n` [`AbiParamSpec`] whose strings are null or
/// NUL-terminated.
pub(crate) unsafe fn read_params(
    ptr: *const AbiParamSpec,
    n: usize,
) -> Result<&'static [ParamSpec], String> {
    if n > MAX_PARAMS {
        return Err(format!(
            "invalid table: {n} parameters (at most {MAX_PARAMS})"
        ));
    }
    let raw: &[AbiParamSpec] = if n == 0 {
        &[]
    } else if ptr.is_null() {
        return Err("invalid table: the parameter array is a null pointer".into());
    } else {
        // SAFETY: non-null, `n` entries (function contract), bounded above.
        unsafe { std::slice::from_raw_parts(ptr, n) }
    };
    let mut params: Vec<ParamSpec> = Vec::with_capacity(raw.len());
    for (i, p) in raw.iter().enumerate() {
        // SAFETY: parameter strings are null or NUL-terminated (contract).
        let name = unsafe { text(p.name, &format!("the name of parameter {i}")) }?;
        // SAFETY: as above.
        let unit = unsafe { text(p.unit, &format!("the unit of parameter `{name}`")) }?;
        // SAFETY: as above.
        let doc = unsafe { text(p.doc, &format!("the doc of parameter `{name}`")) }?;
        if name.is_empty() || params.iter().any(|q| q.name == name) {
            return Err(format!(
                "invalid table: parameter name `{name}` is empty or repeated"
            ));
        }
        if p.min.is_nan() || p.max.is_nan() || p.min > p.max {
            return Err(format!(
                "invalid table: parameter `{name}` has range [{}, {}]",
                p.min, p.max
            ));
        }
        let spec = ParamSpec {
            name: leak(name),
            unit: leak(unit),
            default: (p.has_default != 0).then_some(p.default_value),
            min: p.min,
            min_exclusive: p.min_exclusive != 0,
            max: p.max,
            doc: leak(doc),
        };
        if let Some(d) = spec.default
            && !spec.accepts(d)
        {
            return Err(format!(
                "invalid table: default {d} {} of parameter `{}` is outside its range {}",
                spec.unit,
                spec.name,
                spec.range_text()
            ));
        }
        params.push(spec);
    }
    Ok(Box::leak(params.into_boxed_slice()))
}

/// The plugin's last error message on this thread (through its
/// `last_error`), or `fallback` if it has none; `…` marks a cut message.
#[cold]
pub(crate) fn plugin_message(last_error: LastErrorFn, fallback: &str) -> String {
    let mut buf = [0 as c_char; ERROR_BUFFER];
    // SAFETY: `buf` is writable for its length (the `last_error` contract).
    let len = unsafe { last_error(buf.as_mut_ptr(), buf.len()) };
    if len == 0 {
        return fallback.to_string();
    }
    buf[ERROR_BUFFER - 1] = 0;
    // SAFETY: `last_error` NUL-terminates what it writes into `buf` (ABI
    // contract); the last byte is forced to NUL in case it does not.
    let text = unsafe { CStr::from_ptr(buf.as_ptr()) }
        .to_string_lossy()
        .into_owned();
    if len > text.len() {
        format!("{text}…")
    } else {
        text
    }
}

/// The NUL-terminated message `create` wrote into `buf`, or `no message`.
pub(crate) fn buffer_message(buf: &mut [c_char; ERROR_BUFFER]) -> String {
    buf[ERROR_BUFFER - 1] = 0;
    // SAFETY: the last byte is NUL, so the buffer holds a terminated string.
    let message = unsafe { CStr::from_ptr(buf.as_ptr()) }
        .to_string_lossy()
        .into_owned();
    if message.is_empty() {
        "no message".to_string()
    } else {
        message
    }
}
