//! The state file of forming in stages (docs/stages.md): the blank's whole
//! state after a run (`formsim run --save-state FILE`), read back by a
//! scene's `blank.initial_state`.
//!
//! A small little-endian binary format, so that every number comes back
//! bit for bit: the magic `FSMSTATE`, the format version
//! ([`FORMAT_VERSION`]), the formsim version, the element and material
//! kind, the mesh (node and element counts, connectivity), then the
//! solver's [`SolverResume`] (nodes, forces, time steps, tools, each
//! effect's named arrays). [`read`] refuses a file that is not a state, of
//! another format or formsim version, with one line naming what differs;
//! [`StateFile::check_model`] refuses another element, material or mesh.

mod decode;
mod encode;

pub use decode::read;
pub use encode::write;

use fem_core::SolverResume;

/// The eight bytes a state file starts with.
pub const MAGIC: &[u8; 8] = b"FSMSTATE";

/// The version of the layout this formsim writes and reads.
pub const FORMAT_VERSION: u32 = 1;

/// The formsim version a state records and must match.
pub const FORMSIM_VERSION: &str = env!("CARGO_PKG_VERSION");

/// A state file in memory.
#[derive(Debug, Clone, PartialEq)]
pub struct StateFile {
    /// `blank.element` of the run that saved it.
    pub element: String,
    /// The resolved material model of that run.
    pub material: String,
    /// The blank's quads (0-based node indices).
    pub quads: Vec<[u32; 4]>,
    /// The solver's state.
    pub resume: SolverResume,
}

/// What a scene's model must match to start from a state.
#[derive(Debug, Clone, Copy)]
pub struct ModelKey<'a> {
    /// `blank.element`.
    pub element: &'a str,
    /// The resolved material model.
    pub material: &'a str,
    /// Number of nodes of the blank.
    pub nodes: usize,
    /// The blank's quads.
    pub quads: &'a [[u32; 4]],
}

impl StateFile {
    /// Number of nodes.
    pub fn nodes(&self) -> usize {
        self.resume.nodes.len()
    }

    /// Refuse a model this state does not fit: another element
    /// formulation, material kind, node or element count, or connectivity.
    ///
    /// # Errors
    /// One line naming what differs.
    pub fn check_model(&self, key: &ModelKey<'_>) -> Result<(), String> {
        if self.element != key.element {
            return Err(format!(
                "element `{}` in the state, `{}` in the scene",
                self.element, key.element
            ));
        }
        if self.material != key.material {
            return Err(format!(
                "material model `{}` in the state, `{}` in the scene",
                self.material, key.material
            ));
        }
        if self.nodes() != key.nodes {
            return Err(format!(
                "{} nodes in the state, {} in the scene's mesh",
                self.nodes(),
                key.nodes
            ));
        }
        if self.quads.len() != key.quads.len() {
            return Err(format!(
                "{} elements in the state, {} in the scene's mesh",
                self.quads.len(),
                key.quads.len()
            ));
        }
        if let Some(e) = (0..self.quads.len()).find(|&e| self.quads[e] != key.quads[e]) {
            return Err(format!(
                "element {e} has nodes {:?} in the state, {:?} in the scene's mesh",
                self.quads[e], key.quads[e]
            ));
        }
        Ok(())
    }
}

/// FNV-1a (64 bits) of `bytes` as 16 hex digits: the checksum
/// `summary.json` records for the state a run started from.
pub fn checksum(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}
