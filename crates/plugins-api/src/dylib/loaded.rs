//! A loaded plugin of either kind on the host side: the table read and
//! checked once ([`Shared`]: the library, the copied texts and schema, the
//! functions), and the values the plugin creates from it ([`Instance`]: a
//! live handle, destroyed once). The friction loader
//! ([`crate::loader`]) and the material loader ([`crate::material::loader`])
//! add their kind's functions and their own error types on top.

use std::ffi::{c_char, c_void};
use std::path::Path;
use std::sync::Arc;

use libloading::Library;

use super::{
    ERROR_BUFFER, buffer_message, function, is_key, leak, load_table, plugin_message, read_params,
};
use crate::abi::__private::PANIC_PREFIX;
use crate::abi::{CreateFn, DestroyFn, LastErrorFn, STATUS_OK, STATUS_PANIC};
use crate::table::HasHeader;
use crate::{ABI_VERSION, FrictionError, ParamSpec, Params, check_values};

/// A plugin table as the host loads it: the shared [`Header`](crate::table::Header)
/// and what the kind keeps of the rest.
pub(crate) trait PluginTable: HasHeader {
    /// The kind's own functions and fields, checked.
    type Rest: Send + Sync + 'static;

    /// Check the kind's own functions and fields of a table whose version
    /// matches (after the shared functions, name and summary, before the
    /// parameter schema).
    ///
    /// # Errors
    /// What is wrong, as `invalid table: …`.
    fn rest(&self) -> Result<Self::Rest, String>;
}

/// A table that could not be used: the path as shown and what is wrong.
pub(crate) struct LoadError {
    /// The path, as given.
    pub(crate) path: String,
    /// What is wrong.
    pub(crate) reason: String,
}

/// Why `create` gave no handle.
pub(crate) enum CreateError {
    /// The values do not fit the schema (count, ranges).
    Values(FrictionError),
    /// The plugin refused the values: the status it returned and its message.
    Refused {
        /// `STATUS_ERROR` or a status unknown to this formsim.
        status: i32,
        /// The plugin's message.
        message: String,
    },
    /// The plugin panicked: the panic's message (without `panicked: `).
    Panicked(String),
    /// The plugin reported success but returned a null handle.
    NullHandle,
}

/// What the plugin said about a failed call.
pub(crate) enum Reported {
    /// It panicked: the panic's message (without `panicked: `).
    Panicked(String),
    /// It failed otherwise: its message.
    Failed(String),
}

/// A table read, checked and copied, and the library that holds its code:
/// what a library and every value created from it share.
pub(crate) struct Shared<Tab: PluginTable> {
    /// Path the library was opened from, as given.
    pub(crate) path: String,
    /// ABI version of the table (equal to [`ABI_VERSION`]).
    pub(crate) abi_version: u32,
    /// Name as typed in scenes.
    pub(crate) name: &'static str,
    /// One-line summary.
    pub(crate) summary: &'static str,
    /// Parameter schema.
    pub(crate) params: &'static [ParamSpec],
    /// The kind's own functions and fields.
    pub(crate) rest: Tab::Rest,
    create: CreateFn,
    destroy: DestroyFn,
    last_error: LastErrorFn,
    /// Keeps the code of the functions mapped; `None` only for tables that
    /// live in the host executable itself.
    _library: Option<Library>,
}

impl<Tab: PluginTable> Shared<Tab> {
    /// Load the plugin at `path` and check its table (see
    /// [`crate::loader::PluginLibrary::open`] for what is checked).
    ///
    /// # Errors
    /// The path and what is wrong: file not found, not a shared library, not
    /// a plugin of this kind, ABI version mismatch, an invalid table.
    pub(crate) fn open(path: &Path) -> Result<Arc<Self>, LoadError> {
        let shown = path.display().to_string();
        let opened = load_table::<Tab>(path).and_then(|(library, table)| {
            // SAFETY: non-null, a table living as long as the library (ABI
            // contract); `from_table` reads its version first.
            unsafe { Self::from_table(table, shown.clone(), Some(library)) }
        });
        opened.map(Arc::new).map_err(|reason| LoadError {
            path: shown,
            reason,
        })
    }

    /// Read, check and copy a table.
    ///
    /// # Safety
    /// `table` is non-null and points to at least a `u32` (the version); if
    /// that equals [`ABI_VERSION`], to a whole table whose pointers are null
    /// or valid as its ABI documents, valid while `library` (or, for `None`,
    /// the process) is.
    pub(crate) unsafe fn from_table(
        table: *const Tab,
        path: String,
        library: Option<Library>,
    ) -> Result<Self, String> {
        // SAFETY: the first field of every table version is the `u32`
        // version, readable per the function contract.
        let abi_version = unsafe { table.cast::<u32>().read() };
        if abi_version != ABI_VERSION {
            return Err(super::version_mismatch(abi_version));
        }
        // SAFETY: the version matches, so the whole v1 table is readable.
        let t = unsafe { table.read() };
        let h = t.header();
        let create = function(h.create, "create")?;
        let destroy = function(h.destroy, "destroy")?;
        let last_error = function(h.last_error, "last_error")?;
        let noun = Tab::NOUN;
        // SAFETY: table strings are null or NUL-terminated (ABI contract).
        let name = unsafe { super::text(h.name, &format!("the {noun} name")) }?;
        if !is_key(&name) {
            return Err(format!(
                "invalid table: {noun} name `{name}` must be made of a-z, 0-9, `-`, `_`"
            ));
        }
        // SAFETY: as above.
        let summary = unsafe { super::text(h.summary, "the summary") }?;
        let rest = t.rest()?;
        // SAFETY: `params` is null or holds `n_params` entries whose strings
        // are null or NUL-terminated (ABI contract).
        let params = unsafe { read_params(h.params, h.n_params) }?;
        Ok(Self {
            path,
            abi_version,
            name: leak(name),
            summary: leak(summary),
            params,
            rest,
            create,
            destroy,
            last_error,
            _library: library,
        })
    }

    /// The plugin's last error message on this thread, or `fallback`.
    #[cold]
    pub(crate) fn message(&self, fallback: &str) -> String {
        plugin_message(self.last_error, fallback)
    }

    /// What the plugin says about a call that returned `status`: a panic
    /// for `STATUS_PANIC`, else a failure, with its `last_error` message.
    #[cold]
    pub(crate) fn reported(&self, status: i32) -> Reported {
        let text = self.message("no message");
        if status == STATUS_PANIC {
            Reported::Panicked(without_panic_prefix(&text).to_string())
        } else {
            Reported::Failed(text)
        }
    }

    /// Resolve `params` against the schema: one value per entry, defaults
    /// filled in, ranges checked.
    ///
    /// # Errors
    /// An unknown or missing parameter, a value out of range.
    pub(crate) fn resolve(&self, params: &Params) -> Result<Vec<f64>, FrictionError> {
        params.resolve(self.name, self.params)
    }

    /// Create a value from one value per schema entry, in schema order.
    ///
    /// # Errors
    /// See [`CreateError`].
    pub(crate) fn create(self: &Arc<Self>, values: &[f64]) -> Result<Instance<Tab>, CreateError> {
        check_values(self.name, self.params, values).map_err(CreateError::Values)?;
        let mut handle: *mut c_void = std::ptr::null_mut();
        let mut buf = [0 as c_char; ERROR_BUFFER];
        // SAFETY: `values` holds `values.len()` readable values, `handle` and
        // `buf` are writable (the `create` contract).
        let status = unsafe {
            (self.create)(
                values.as_ptr(),
                values.len(),
                &mut handle,
                buf.as_mut_ptr(),
                buf.len(),
            )
        };
        if status != STATUS_OK {
            let message = buffer_message(&mut buf);
            return Err(if status == STATUS_PANIC {
                CreateError::Panicked(without_panic_prefix(&message).to_string())
            } else {
                CreateError::Refused { status, message }
            });
        }
        if handle.is_null() {
            return Err(CreateError::NullHandle);
        }
        Ok(Instance {
            handle,
            shared: Arc::clone(self),
        })
    }
}

/// `text` without the `panicked: ` of a caught panic.
pub(crate) fn without_panic_prefix(text: &str) -> &str {
    text.strip_prefix(PANIC_PREFIX).unwrap_or(text)
}

/// A live handle from `create`, with the table it came from; destroyed
/// exactly once, when dropped (before the library can be unloaded: the
/// [`Shared`] it holds is dropped after).
pub(crate) struct Instance<Tab: PluginTable> {
    handle: *mut c_void,
    shared: Arc<Shared<Tab>>,
}

// SAFETY: the handle is owned by this value alone (destroyed once, in
// `Drop`); the ABI of either kind requires the functions taking a handle to
// be callable concurrently with the same handle (the macros' shims only take
// `&T` with `T: Send + Sync`), and `destroy` may run on any thread.
unsafe impl<Tab: PluginTable> Send for Instance<Tab> {}
// SAFETY: as for `Send`: shared access only calls the thread-safe table
// functions.
unsafe impl<Tab: PluginTable> Sync for Instance<Tab> {}

impl<Tab: PluginTable> Instance<Tab> {
    /// The handle, live as long as `self`.
    #[inline]
    pub(crate) fn handle(&self) -> *mut c_void {
        self.handle
    }

    /// The table and library the handle belongs to.
    #[inline]
    pub(crate) fn shared(&self) -> &Shared<Tab> {
        &self.shared
    }
}

impl<Tab: PluginTable> Drop for Instance<Tab> {
    fn drop(&mut self) {
        // SAFETY: `handle` came from `create` and is destroyed exactly once,
        // here; the library (in `shared`) is dropped after this call.
        unsafe { (self.shared.destroy)(self.handle) };
    }
}
