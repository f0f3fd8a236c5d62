//! Reading a state file back, refusing what it cannot take (one line each).

use super::{FORMAT_VERSION, FORMSIM_VERSION, MAGIC, StateFile};
use fem_core::resume::unflatten;
use fem_core::{Forces, Mat3, NodalState, SolverResume, StateArrays, ToolLoad, ToolResume, Vec3};
use plugins_api::{RigidPose, RigidVelocity};
use std::path::Path;

/// A cursor over the bytes; `Err(what)` when they end inside `what`.
struct In<'a> {
    bytes: &'a [u8],
    at: usize,
}

type Read<T> = Result<T, String>;

impl In<'_> {
    fn take(&mut self, n: usize, what: &str) -> Read<&[u8]> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end =
            end.ok_or_else(|| format!("the file ends inside {what}: truncated or damaged"))?;
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn u32(&mut self, what: &str) -> Read<u32> {
        let b = self.take(4, what)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn u64(&mut self, what: &str) -> Read<usize> {
        let b = self.take(8, what)?;
        let v = u64::from_le_bytes(b.try_into().map_err(|_| what.to_string())?);
        usize::try_from(v).map_err(|_| format!("{what}: length {v} too large"))
    }
    fn f64(&mut self, what: &str) -> Read<f64> {
        let b = self.take(8, what)?;
        Ok(f64::from_le_bytes(
            b.try_into().map_err(|_| what.to_string())?,
        ))
    }
    fn str(&mut self, what: &str) -> Read<String> {
        let n = self.u64(what)?;
        let b = self.take(n, what)?;
        String::from_utf8(b.to_vec()).map_err(|_| format!("{what} is not UTF-8: damaged file"))
    }
    fn f64s(&mut self, what: &str) -> Read<Vec<f64>> {
        let n = self.u64(what)?;
        let b = self.take(n.saturating_mul(8), what)?;
        Ok(b.chunks_exact(8)
            .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
            .collect())
    }
    fn f64s_of(&mut self, len: usize, what: &str) -> Read<Vec<f64>> {
        let v = self.f64s(what)?;
        if v.len() != len {
            return Err(format!(
                "{what}: {} values, {len} expected: damaged file",
                v.len()
            ));
        }
        Ok(v)
    }
    fn vec3s(&mut self, n: usize, what: &str) -> Read<Vec<Vec3>> {
        let flat = self.f64s_of(3 * n, what)?;
        let mut out = vec![Vec3::zeros(); n];
        unflatten(&flat, &mut out);
        Ok(out)
    }
    fn vec3(&mut self, what: &str) -> Read<Vec3> {
        Ok(Vec3::new(self.f64(what)?, self.f64(what)?, self.f64(what)?))
    }
    fn option(&mut self, what: &str) -> Read<Option<f64>> {
        let (has, v) = (self.f64(what)?, self.f64(what)?);
        Ok((has == 1.0).then_some(v))
    }
    fn pose(&mut self, what: &str) -> Read<RigidPose> {
        let translation = self.vec3(what)?;
        let mut m = [0.0; 9];
        for x in &mut m {
            *x = self.f64(what)?;
        }
        Ok(RigidPose {
            translation,
            rotation: Mat3::from_column_slice(&m),
        })
    }
    fn tool(&mut self) -> Read<ToolResume> {
        let what = "a tool";
        Ok(ToolResume {
            name: self.str(what)?,
            initial: self.pose(what)?,
            pose: self.pose(what)?,
            velocity: RigidVelocity {
                linear: self.vec3(what)?,
                angular: self.vec3(what)?,
            },
            free_speed: self.f64(what)?,
            applied: self.option(what)?,
            last_reaction: self.option(what)?,
            load: ToolLoad {
                force: self.vec3(what)?,
                stiffness: self.f64(what)?,
            },
        })
    }
    fn arrays(&mut self) -> Read<(String, StateArrays)> {
        let name = self.str("an effect's name")?;
        let what = format!("the state of `{name}`");
        let n = self.u64(&what)?;
        let mut entries = Vec::new();
        for _ in 0..n {
            let key = self.str(&what)?;
            entries.push((key, self.f64s(&what)?));
        }
        Ok((name, StateArrays::from_entries(entries)))
    }
}

/// The header: magic, format version and formsim version, each refused
/// when it is not this formsim's.
fn header(i: &mut In<'_>) -> Read<()> {
    if i.bytes.len() < MAGIC.len() || &i.bytes[..MAGIC.len()] != MAGIC {
        return Err("not a formsim state file (it does not start with `FSMSTATE`)".into());
    }
    i.at = MAGIC.len();
    let format = i.u32("the format version")?;
    if format != FORMAT_VERSION {
        return Err(format!(
            "state format version {format}; this formsim reads version {FORMAT_VERSION}"
        ));
    }
    let version = i.str("the formsim version")?;
    if version != FORMSIM_VERSION {
        return Err(format!(
            "saved by formsim {version}; this is formsim {FORMSIM_VERSION}"
        ));
    }
    Ok(())
}

/// The state in `bytes`.
///
/// # Errors
/// What makes it unreadable here, one line.
pub fn from_bytes(bytes: &[u8]) -> Read<StateFile> {
    let mut i = In { bytes, at: 0 };
    header(&mut i)?;
    let element = i.str("the element")?;
    let material = i.str("the material")?;
    let nodes = i.u64("the node count")?;
    let elements = i.u64("the element count")?;
    let mut quads = Vec::with_capacity(elements.min(bytes.len() / 16));
    for _ in 0..elements {
        let mut q = [0u32; 4];
        for a in &mut q {
            *a = i.u32("the connectivity")?;
        }
        quads.push(q);
    }
    let n = nodes;
    let nodal = NodalState {
        x0: i.vec3s(n, "x0")?,
        x: i.vec3s(n, "x")?,
        v: i.vec3s(n, "v")?,
        w: i.vec3s(n, "w")?,
        mass: Vec::new(),
        inertia: Vec::new(),
    };
    let forces = Forces {
        f: i.vec3s(n, "f")?,
        m: i.vec3s(n, "m")?,
    };
    let nodal = NodalState {
        mass: i.f64s_of(n, "mass")?,
        inertia: i.f64s_of(n, "inertia")?,
        ..nodal
    };
    let s = "the time steps";
    let time = i.f64(s)?;
    let (dt_prev, dt_next, dt_floor) = (i.f64(s)?, i.f64(s)?, i.f64(s)?);
    let (physical_mass, added_mass) = (i.f64(s)?, i.f64(s)?);
    let tools = (0..i.u64("the tool count")?)
        .map(|_| i.tool())
        .collect::<Read<Vec<_>>>()?;
    let effects = (0..i.u64("the effect count")?)
        .map(|_| i.arrays())
        .collect::<Read<Vec<_>>>()?;
    let mut words = [0.0; 19];
    for w in &mut words {
        *w = i.f64("the energy ledger")?;
    }
    if i.at != bytes.len() {
        return Err(format!(
            "{} bytes after the last section: damaged file",
            bytes.len() - i.at
        ));
    }
    Ok(StateFile {
        element,
        material,
        quads,
        resume: SolverResume {
            nodes: nodal,
            forces,
            time,
            dt_prev,
            dt_next,
            dt_floor,
            physical_mass,
            added_mass,
            tools,
            effects,
            ledger: fem_core::EnergyLedger::from_words(&words),
        },
    })
}

/// Read the state at `path`, with its checksum.
///
/// # Errors
/// The file cannot be read or is refused: one line naming the file and
/// what differs.
pub fn read(path: &Path) -> Result<(StateFile, String), String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let state = from_bytes(&bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok((state, super::checksum(&bytes)))
}
