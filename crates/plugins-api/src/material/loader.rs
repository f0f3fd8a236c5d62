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

use std::path::Path;
use std::sync::{Arc, OnceLock};

use thiserror::Error;

use super::abi::{
    AbiMaterialBatch, ElasticFn, InitialStateFn, MaterialPluginV1, STATUS_OK, UpdateFn,
};
use super::{Elastic, MAX_STATE, PointResult};
use crate::dylib::{self, CreateError, Instance, PluginTable, Reported, Shared};
use crate::{ParamSpec, Params};

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

/// The material's own part of its table, checked at load.
pub(crate) struct MaterialRest {
    elastic: ElasticFn,
    initial_state: InitialStateFn,
    update: UpdateFn,
    n_state: usize,
    isotropic: bool,
}

impl PluginTable for MaterialPluginV1 {
    type Rest = MaterialRest;

    fn rest(&self) -> Result<MaterialRest, String> {
        let elastic = dylib::function(self.elastic, "elastic")?;
        let initial_state = dylib::function(self.initial_state, "initial_state")?;
        let update = dylib::function(self.update, "update")?;
        if self.n_state > MAX_STATE || self.isotropic > 1 {
            return Err(format!(
                "invalid table: n_state = {} (at most {MAX_STATE}), isotropic = {} (0 or 1)",
                self.n_state, self.isotropic
            ));
        }
        Ok(MaterialRest {
            elastic,
            initial_state,
            update,
            n_state: self.n_state,
            isotropic: self.isotropic == 1,
        })
    }
}

impl Shared<MaterialPluginV1> {
    /// The error for what the plugin reported about `call`.
    #[cold]
    fn error(&self, call: String, reported: Reported) -> MaterialPluginError {
        let (name, path) = (self.name.to_string(), self.path.clone());
        match reported {
            Reported::Panicked(message) => MaterialPluginError::Panicked {
                name,
                path,
                call,
                message,
            },
            Reported::Failed(message) => MaterialPluginError::Failed {
                name,
                path,
                call,
                message,
            },
        }
    }

    /// The error for a failed call (`status`), with the plugin's message.
    #[cold]
    fn failure(&self, status: i32, call: String) -> MaterialPluginError {
        self.error(call, self.reported(status))
    }

    /// The error for a call whose values cannot be used.
    fn failed(&self, call: String, message: String) -> MaterialPluginError {
        self.error(call, Reported::Failed(message))
    }
}

/// A material plugin loaded from a shared library. Cheap to clone.
#[derive(Clone)]
pub struct MaterialLibrary {
    shared: Arc<Shared<MaterialPluginV1>>,
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
        let shared = Shared::open(path.as_ref()).map_err(|e| MaterialPluginError::Load {
            path: e.path,
            reason: e.reason,
        })?;
        Ok(Self { shared })
    }

    /// The material type `T` of this process through the same table and
    /// shims a plugin of it would export: for testing a material (and the
    /// conformance suite) before building it as a `cdylib`. Leaks the table
    /// (a few hundred bytes per call).
    ///
    /// # Errors
    /// As [`Self::open`] for an invalid table.
    pub fn linked<T: super::UserMaterial>() -> Result<Self, MaterialPluginError> {
        let cell = Box::leak(Box::new(OnceLock::new()));
        let table = crate::abi::__private::entry::<MaterialPluginV1, T>(cell);
        let path = format!("linked into this program: {}", std::any::type_name::<T>());
        let shared = if table.is_null() {
            Err("the table could not be built".into())
        } else {
            // SAFETY: a table of this process's shims, leaked: valid for ever.
            unsafe { Shared::from_table(table, path.clone(), None) }
        };
        match shared {
            Ok(shared) => Ok(Self {
                shared: Arc::new(shared),
            }),
            Err(reason) => Err(MaterialPluginError::Load { path, reason }),
        }
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
        self.shared.rest.n_state
    }
    /// Whether the plugin declares an isotropic response.
    pub fn isotropic(&self) -> bool {
        self.shared.rest.isotropic
    }

    /// Resolve `params` against the schema (defaults, ranges) and create the material.
    ///
    /// # Errors
    /// As [`Self::instantiate`], and an unknown or missing parameter.
    pub fn build(&self, params: &Params) -> Result<DynamicMaterial, MaterialPluginError> {
        let values = self
            .shared
            .resolve(params)
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
        let instance = shared.create(values).map_err(|e| match e {
            CreateError::Values(e) => MaterialPluginError::Params(e.to_string()),
            CreateError::Refused { message, .. } => MaterialPluginError::Params(format!(
                "invalid parameters of material plugin {}: {message}",
                shared.name
            )),
            CreateError::Panicked(message) => {
                shared.error("create".into(), Reported::Panicked(message))
            }
            CreateError::NullHandle => {
                shared.failed("create".into(), "returned a null handle".into())
            }
        })?;
        let mut elastic = Elastic {
            young: f64::NAN,
            poisson: f64::NAN,
            density: f64::NAN,
        };
        // SAFETY: live handle, writable `elastic`.
        let status = unsafe { (shared.rest.elastic)(instance.handle(), &mut elastic) };
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

/// A user material living in a plugin, called through its C-ABI table.
/// Cheap to clone (the handle is shared; it is destroyed when the last
/// clone goes).
#[derive(Clone)]
pub struct DynamicMaterial {
    instance: Arc<Instance<MaterialPluginV1>>,
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
        self.instance.shared().name
    }
    /// Path of the library.
    pub fn path(&self) -> &str {
        &self.instance.shared().path
    }
    /// State variables per point.
    pub fn n_state(&self) -> usize {
        self.instance.shared().rest.n_state
    }
    /// Whether the plugin declares an isotropic response.
    pub fn isotropic(&self) -> bool {
        self.instance.shared().rest.isotropic
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
        let shared = self.instance.shared();
        assert_eq!(state.len(), shared.rest.n_state, "state length");
        let mut flow = f64::NAN;
        // SAFETY: live handle; `state` writable for `n_state`; `flow` writable.
        let status = unsafe {
            (shared.rest.initial_state)(self.instance.handle(), state.as_mut_ptr(), &mut flow)
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
        let shared = self.instance.shared();
        let n_state = shared.rest.n_state;
        let n = deps.len();
        assert!(
            stress.len() == n && result.len() == n && state.len() == n * n_state,
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
        let status = unsafe { (shared.rest.update)(self.instance.handle(), &batch, &mut failed) };
        if status != STATUS_OK {
            let at = failed.min(n.saturating_sub(1));
            return Err(shared.failure(status, point_call(at, &deps[at])));
        }
        for (i, (s, r)) in stress.iter().zip(result.iter()).enumerate() {
            let st = &state[i * n_state..(i + 1) * n_state];
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
