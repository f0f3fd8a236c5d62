//! Loading user materials from shared libraries through the C-ABI table of
//! [`super::abi`].
//!
//! [`MaterialLibrary::open`] loads a `cdylib`, finds
//! `formsim_material_plugin_v1`, checks the table (version first, then
//! function pointers, texts, parameter schema, `n_state ≤ MAX_STATE`) and
//! copies its texts into host memory. [`MaterialLibrary::build`] resolves
//! the parameters against the schema and creates a [`DynamicMaterial`],
//! whose elastic constants are read and checked once.
//!
//! [`DynamicMaterial::update`] calls the plugin for a batch of points and
//! checks what comes back: a non-finite stress, state or result is an error
//! naming the point and the quantity, like a panic or an error reported by
//! the plugin. Nothing
//! from a plugin unwinds into the host. The opening contract (a library is
//! trusted like the formsim binary) is that of the friction loader,
//! [`crate::loader::PluginLibrary::open`].

use std::ffi::{c_char, c_void};
use std::path::Path;
use std::sync::Arc;

use libloading::Library;
use thiserror::Error;

use super::abi::{
    AbiMaterialBatch, ElasticFn, InitialStateFn, MaterialPluginV1, STATUS_OK, STATUS_PANIC,
    UpdateFn,
};
use super::{Elastic, MAX_STATE, PointResult};
use crate::abi::__private::PANIC_PREFIX;
use crate::abi::{CreateFn, DestroyFn, LastErrorFn};
use crate::{ABI_VERSION, ParamSpec, Params, check_values, dylib};

/// What can go wrong with a material plugin; every message names the plugin.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MaterialPluginError {
    /// The library cannot be used: not found, not a material plugin, wrong
    /// ABI version, an invalid table.
    #[error("material plugin {path}: {reason}")]
    Load {
        /// Path of the shared library.
        path: String,
        /// What is wrong.
        reason: String,
    },
    /// Parameters refused by the schema or by the plugin.
    #[error("{0}")]
    Params(String),
    /// Code inside the plugin panicked (caught in the plugin).
    #[error("material plugin {name} panicked: {message}; in {call} ({path})")]
    Panicked {
        /// The material's name.
        name: String,
        /// Path of the shared library.
        path: String,
        /// The call, with the point and its inputs.
        call: String,
        /// The panic's message and where it happened.
        message: String,
    },
    /// The plugin reported an error, or returned values that cannot be used.
    #[error("material plugin {name} failed: {message}; in {call} ({path})")]
    Failed {
        /// The material's name.
        name: String,
        /// Path of the shared library.
        path: String,
        /// The call, with the point and its inputs.
        call: String,
        /// What went wrong.
        message: String,
    },
}

/// The table's function pointers, checked non-null at load.
#[derive(Clone, Copy)]
struct Functions {
    create: CreateFn,
    destroy: DestroyFn,
    elastic: ElasticFn,
    initial_state: InitialStateFn,
    update: UpdateFn,
    last_error: LastErrorFn,
}

/// A table read, checked and copied, and the library that holds its code.
struct Shared {
    path: String,
    name: &'static str,
    summary: &'static str,
    params: &'static [ParamSpec],
    n_state: usize,
    isotropic: bool,
    functions: Functions,
    /// Keeps the code mapped; `None` only for tables of the host itself (tests).
    _library: Option<Library>,
}

impl Shared {
    /// The error for a failed call (`status`), with the plugin's message.
    #[cold]
    fn failure(&self, status: i32, call: String) -> MaterialPluginError {
        let text = dylib::plugin_message(self.functions.last_error, "no message");
        let (name, path) = (self.name.to_string(), self.path.clone());
        match text.strip_prefix(PANIC_PREFIX) {
            Some(message) if status == STATUS_PANIC => MaterialPluginError::Panicked {
                name,
                path,
                call,
                message: message.to_string(),
            },
            _ => MaterialPluginError::Failed {
                name,
                path,
                call,
                message: text,
            },
        }
    }

    fn failed(&self, call: String, message: String) -> MaterialPluginError {
        MaterialPluginError::Failed {
            name: self.name.to_string(),
            path: self.path.clone(),
            call,
            message,
        }
    }
}

/// A material plugin loaded from a shared library. Cheap to clone.
#[derive(Clone)]
pub struct MaterialLibrary {
    shared: Arc<Shared>,
}

impl std::fmt::Debug for MaterialLibrary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MaterialLibrary")
            .field("name", &self.shared.name)
            .field("path", &self.shared.path)
            .finish_non_exhaustive()
    }
}

impl MaterialLibrary {
    /// Load the material plugin at `path` and check its table.
    ///
    /// # Errors
    /// [`MaterialPluginError::Load`] naming the path and what is wrong.
    pub fn open(path: impl AsRef<Path>) -> Result<Self, MaterialPluginError> {
        let path = path.as_ref();
        let shown = path.display().to_string();
        let error = |reason: String| MaterialPluginError::Load {
            path: shown.clone(),
            reason,
        };
        let (library, table) =
            dylib::load_table::<MaterialPluginV1>(path, "material", "formsim_material_plugin_v")
                .map_err(error)?;
        // SAFETY: non-null, a table living as long as the library (ABI contract).
        unsafe { Self::from_table(table, shown.clone(), Some(library)) }.map_err(error)
    }

    /// The material type `T` of this process through the same table and
    /// shims a plugin of it would export: for testing a material (and the
    /// conformance suite) before building it as a `cdylib`. Leaks the table
    /// (a few hundred bytes per call).
    ///
    /// # Errors
    /// As [`Self::open`] for an invalid table.
    pub fn linked<T: super::UserMaterial>() -> Result<Self, MaterialPluginError> {
        let cell = Box::leak(Box::new(std::sync::OnceLock::new()));
        let table = crate::abi::__private::entry::<MaterialPluginV1, T>(cell);
        let path = format!("linked into this program: {}", std::any::type_name::<T>());
        let error = |reason| MaterialPluginError::Load {
            path: path.clone(),
            reason,
        };
        if table.is_null() {
            return Err(error("the table could not be built".into()));
        }
        // SAFETY: a table of this process's shims, leaked: valid for ever.
        unsafe { Self::from_table(table, path.clone(), None) }.map_err(error)
    }

    /// Read and check a table.
    ///
    /// # Safety
    /// `table` is non-null and points to at least a `u32`; if that equals
    /// [`ABI_VERSION`], to a whole [`MaterialPluginV1`] honouring the
    /// contracts of [`super::abi`], valid while `library` (or the process,
    /// for `None`) is.
    pub(crate) unsafe fn from_table(
        table: *const MaterialPluginV1,
        path: String,
        library: Option<Library>,
    ) -> Result<Self, String> {
        // SAFETY: the version is the first field of every table version.
        let abi_version = unsafe { std::ptr::addr_of!((*table).abi_version).read() };
        if abi_version != ABI_VERSION {
            return Err(dylib::version_mismatch(abi_version));
        }
        // SAFETY: the version matches, so the whole v1 table is readable.
        let t = unsafe { table.read() };
        let missing = |what: &str| format!("invalid table: function `{what}` is a null pointer");
        let functions = Functions {
            create: t.create.ok_or_else(|| missing("create"))?,
            destroy: t.destroy.ok_or_else(|| missing("destroy"))?,
            elastic: t.elastic.ok_or_else(|| missing("elastic"))?,
            initial_state: t.initial_state.ok_or_else(|| missing("initial_state"))?,
            update: t.update.ok_or_else(|| missing("update"))?,
            last_error: t.last_error.ok_or_else(|| missing("last_error"))?,
        };
        // SAFETY: table strings are null or NUL-terminated (ABI contract).
        let name = unsafe { dylib::text(t.name, "the material name") }?;
        if !dylib::is_key(&name) {
            return Err(format!(
                "invalid table: material name `{name}` must be made of a-z, 0-9, `-`, `_`"
            ));
        }
        // SAFETY: as above.
        let summary = unsafe { dylib::text(t.summary, "the summary") }?;
        if t.n_state > MAX_STATE || t.isotropic > 1 {
            return Err(format!(
                "invalid table: n_state = {} (at most {MAX_STATE}), isotropic = {} (0 or 1)",
                t.n_state, t.isotropic
            ));
        }
        // SAFETY: null or `n_params` entries with valid strings (ABI contract).
        let params = unsafe { dylib::read_params(t.params, t.n_params) }?;
        Ok(Self {
            shared: Arc::new(Shared {
                path,
                name: dylib::leak(name),
                summary: dylib::leak(summary),
                params,
                n_state: t.n_state,
                isotropic: t.isotropic == 1,
                functions,
                _library: library,
            }),
        })
    }

    /// Path the library was opened from.
    pub fn path(&self) -> &str {
        &self.shared.path
    }
    /// The material's name.
    pub fn name(&self) -> &'static str {
        self.shared.name
    }
    /// One-line summary.
    pub fn summary(&self) -> &'static str {
        self.shared.summary
    }
    /// Parameter schema.
    pub fn params(&self) -> &'static [ParamSpec] {
        self.shared.params
    }
    /// State variables per point.
    pub fn n_state(&self) -> usize {
        self.shared.n_state
    }
    /// Whether the plugin declares an isotropic response.
    pub fn isotropic(&self) -> bool {
        self.shared.isotropic
    }

    /// Resolve `params` against the schema (defaults, ranges) and create the material.
    ///
    /// # Errors
    /// As [`Self::instantiate`], and an unknown or missing parameter.
    pub fn build(&self, params: &Params) -> Result<DynamicMaterial, MaterialPluginError> {
        let values = params
            .resolve(self.name(), self.params())
            .map_err(|e| MaterialPluginError::Params(e.to_string()))?;
        self.instantiate(&values)
    }

    /// Create the material from one value per schema entry.
    ///
    /// # Errors
    /// A value out of range; the plugin's refusal or panic; elastic constants
    /// out of range (E > 0, -1 < ν < 0.5, ρ > 0).
    pub fn instantiate(&self, values: &[f64]) -> Result<DynamicMaterial, MaterialPluginError> {
        let shared = &self.shared;
        check_values(shared.name, shared.params, values)
            .map_err(|e| MaterialPluginError::Params(e.to_string()))?;
        let mut handle: *mut c_void = std::ptr::null_mut();
        let mut buf = [0 as c_char; dylib::ERROR_BUFFER];
        // SAFETY: `values` readable, `handle` and `buf` writable (`create` contract).
        let status = unsafe {
            (shared.functions.create)(
                values.as_ptr(),
                values.len(),
                &mut handle,
                buf.as_mut_ptr(),
                buf.len(),
            )
        };
        if status != STATUS_OK {
            let message = dylib::buffer_message(&mut buf);
            return Err(if status == STATUS_PANIC {
                let message = message.strip_prefix(PANIC_PREFIX).unwrap_or(&message);
                MaterialPluginError::Panicked {
                    name: shared.name.into(),
                    path: shared.path.clone(),
                    call: "create".into(),
                    message: message.into(),
                }
            } else {
                MaterialPluginError::Params(format!(
                    "invalid parameters of material plugin {}: {message}",
                    shared.name
                ))
            });
        }
        if handle.is_null() {
            return Err(shared.failed("create".into(), "returned a null handle".into()));
        }
        let instance = Instance {
            handle,
            shared: Arc::clone(shared),
        };
        let mut elastic = Elastic {
            young: f64::NAN,
            poisson: f64::NAN,
            density: f64::NAN,
        };
        // SAFETY: live handle, writable `elastic`.
        let status = unsafe { (shared.functions.elastic)(handle, &mut elastic) };
        if status != STATUS_OK {
            return Err(shared.failure(status, "elastic".into()));
        }
        elastic
            .check()
            .map_err(|why| shared.failed("elastic".into(), why))?;
        Ok(DynamicMaterial {
            instance: Arc::new(instance),
            elastic,
        })
    }
}

/// A live handle; destroyed when the last [`DynamicMaterial`] sharing it goes.
struct Instance {
    handle: *mut c_void,
    shared: Arc<Shared>,
}

// SAFETY: the handle is owned by this value alone (destroyed once, in
// `Drop`); the ABI requires `elastic`, `initial_state` and `update` to be
// callable concurrently with one handle (the macro's shims take `&T`,
// `T: Send + Sync`), and `destroy` may run on any thread.
unsafe impl Send for Instance {}
// SAFETY: as for `Send`.
unsafe impl Sync for Instance {}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: made by `create`, destroyed exactly once, here; the library
        // (in `shared`) is dropped after this call.
        unsafe { (self.shared.functions.destroy)(self.handle) };
    }
}

/// A user material living in a plugin, called through its C-ABI table.
/// Cheap to clone (the handle is shared).
#[derive(Clone)]
pub struct DynamicMaterial {
    instance: Arc<Instance>,
    elastic: Elastic,
}

impl std::fmt::Debug for DynamicMaterial {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DynamicMaterial")
            .field("name", &self.name())
            .field("path", &self.path())
            .field("elastic", &self.elastic)
            .finish_non_exhaustive()
    }
}

impl DynamicMaterial {
    /// The material's name.
    pub fn name(&self) -> &'static str {
        self.instance.shared.name
    }
    /// Path of the library.
    pub fn path(&self) -> &str {
        &self.instance.shared.path
    }
    /// State variables per point.
    pub fn n_state(&self) -> usize {
        self.instance.shared.n_state
    }
    /// Whether the plugin declares an isotropic response.
    pub fn isotropic(&self) -> bool {
        self.instance.shared.isotropic
    }
    /// Elastic constants and density (read and checked at creation).
    pub fn elastic(&self) -> Elastic {
        self.elastic
    }

    /// Fill `state` (`n_state` values) for a virgin point; its flow stress (MPa).
    ///
    /// # Errors
    /// The plugin's failure, or a non-finite or non-positive flow stress or
    /// non-finite state.
    pub fn initial_state(&self, state: &mut [f64]) -> Result<f64, MaterialPluginError> {
        let shared = &self.instance.shared;
        assert_eq!(state.len(), shared.n_state, "state length");
        let mut flow = f64::NAN;
        // SAFETY: live handle; `state` writable for `n_state`; `flow` writable.
        let status = unsafe {
            (shared.functions.initial_state)(self.instance.handle, state.as_mut_ptr(), &mut flow)
        };
        if status != STATUS_OK {
            return Err(shared.failure(status, "initial_state".into()));
        }
        if !(flow.is_finite() && flow > 0.0) || state.iter().any(|x| !x.is_finite()) {
            return Err(shared.failed(
                "initial_state".into(),
                format!("returned flow stress {flow} MPa and state {state:?}; both must be finite, the flow stress > 0"),
            ));
        }
        Ok(flow)
    }

    /// Advance `deps.len()` points by one step: `stress` and `state`
    /// (`n_state` per point) in place, one [`PointResult`] per point.
    ///
    /// # Errors
    /// The plugin's error or panic, or a non-finite value among its outputs;
    /// each names the point and its inputs. The points' values are then
    /// unspecified.
    ///
    /// # Panics
    /// If the slices' lengths disagree (a bug of the caller).
    pub fn update(
        &self,
        deps: &[[f64; 3]],
        stress: &mut [[f64; 3]],
        state: &mut [f64],
        result: &mut [PointResult],
    ) -> Result<(), MaterialPluginError> {
        let shared = &self.instance.shared;
        let n = deps.len();
        assert!(
            stress.len() == n && result.len() == n && state.len() == n * shared.n_state,
            "batch lengths"
        );
        let batch = AbiMaterialBatch {
            n,
            deps: deps.as_ptr().cast(),
            stress: stress.as_mut_ptr().cast(),
            state: state.as_mut_ptr(),
            result: result.as_mut_ptr(),
        };
        let mut failed = usize::MAX;
        // SAFETY: live handle; the arrays hold `n` points each and do not
        // overlap (distinct Rust slices); `failed` is writable.
        let status =
            unsafe { (shared.functions.update)(self.instance.handle, &batch, &mut failed) };
        if status != STATUS_OK {
            let at = failed.min(n.saturating_sub(1));
            return Err(shared.failure(status, point_call(at, &deps[at])));
        }
        for (i, (s, r)) in stress.iter().zip(result.iter()).enumerate() {
            let st = &state[i * shared.n_state..(i + 1) * shared.n_state];
            let finite = s.iter().chain(st).all(|x| x.is_finite())
                && [r.deps_zz, r.dissipation, r.plastic_strain, r.flow_stress]
                    .iter()
                    .all(|x| x.is_finite());
            if !finite {
                return Err(shared.failed(
                    point_call(i, &deps[i]),
                    format!("returned a non-finite value: σ = {s:?} MPa, state = {st:?}, {r:?}"),
                ));
            }
        }
        Ok(())
    }
}

/// `update at point I (Δε = …)`, for messages.
fn point_call(i: usize, deps: &[f64; 3]) -> String {
    format!("update at point {i} (Δε = {deps:?})")
}
