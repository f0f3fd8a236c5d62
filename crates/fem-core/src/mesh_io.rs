//! Mesh readers: Abaqus `.inp` (nodes, S4/S4R shells, node and element sets) and Gmsh 4.1 ASCII `.msh` (quads, physical groups).

use crate::{FemError, Mesh, Vec3};
use std::collections::{BTreeMap, HashMap};
use std::path::Path;

/// Shell element types of Abaqus accepted by [`read_inp`].
const INP_SHELLS: [&str; 5] = ["S4", "S4R", "S4R5", "S4RS", "S4RSW"];

fn read_text(path: &Path) -> Result<String, FemError> {
    plugins_api::input_file::read_text(path, plugins_api::input_file::MESH_LIMIT).map_err(|e| {
        FemError::Parse {
            file: path.display().to_string(),
            line: 0,
            message: format!("cannot read the file: {e}"),
        }
    })
}

/// Builds errors that name the file and line.
struct At<'a> {
    file: &'a str,
}

impl At<'_> {
    fn err(&self, line: usize, message: impl Into<String>) -> FemError {
        FemError::Parse {
            file: self.file.to_string(),
            line,
            message: message.into(),
        }
    }
}

// ----- Abaqus .inp ---------------------------------------------------------

#[derive(Debug, Clone, PartialEq)]
enum InpBlock {
    None,
    Node,
    Element {
        elset: Option<String>,
    },
    Set {
        node: bool,
        name: String,
        generate: bool,
    },
    Skip,
}

/// Read an Abaqus `.inp` file: `*NODE`, `*ELEMENT, TYPE=S4|S4R|S4R5|S4RS|S4RSW`
/// (with optional `ELSET=`), `*NSET, NSET=…` and `*ELSET, ELSET=…` (with
/// optional `GENERATE`). Other keywords and `**` comments are skipped. File
/// ids become 0-based indices in file order; sets keep their names as
/// written; `all` node and element sets are added unless the file defines
/// them. Errors name the file and line. The mesh is not validated here: call
/// [`Mesh::validate`].
pub fn read_inp(path: impl AsRef<Path>) -> Result<Mesh, FemError> {
    read_inp_numbered(path).map(|f| f.mesh)
}

/// [`read_inp`], keeping the file's node and element ids (for messages).
pub fn read_inp_numbered(path: impl AsRef<Path>) -> Result<MeshFile, FemError> {
    let path = path.as_ref();
    let text = read_text(path)?;
    let file = path.display().to_string();
    parse_inp_numbered(&text, &file)
}

/// A mesh read from a file, with the file's own numbers of its nodes and
/// elements (Abaqus ids, Gmsh tags), so that messages can name them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeshFile {
    /// The mesh (0-based indices in file order).
    pub mesh: Mesh,
    /// The file's id of each node, by index.
    pub node_ids: Vec<i64>,
    /// The file's id of each element, by index.
    pub element_ids: Vec<i64>,
}

#[cfg(test)]
fn parse_inp(text: &str, file: &str) -> Result<Mesh, FemError> {
    parse_inp_numbered(text, file).map(|f| f.mesh)
}

fn parse_inp_numbered(text: &str, file: &str) -> Result<MeshFile, FemError> {
    let mut r = InpReader {
        at: At { file },
        nodes: Vec::new(),
        node_ids: Vec::new(),
        node_index: HashMap::new(),
        elems: Vec::new(),
        elem_index: HashMap::new(),
        sets: BTreeMap::new(),
        block: InpBlock::None,
    };
    for (k, raw) in text.lines().enumerate() {
        let line_no = k + 1;
        let line = raw.trim();
        if line.is_empty() || line.starts_with("**") {
            continue;
        }
        if let Some(kw) = line.strip_prefix('*') {
            r.keyword(line_no, kw)?;
            continue;
        }
        let fields: Vec<&str> = line
            .split(',')
            .map(str::trim)
            .filter(|f| !f.is_empty())
            .collect();
        r.data(line_no, &fields)?;
    }
    r.finish()
}

/// The state of an `.inp` file read line by line.
struct InpReader<'a> {
    at: At<'a>,
    nodes: Vec<Vec3>,
    node_ids: Vec<i64>,
    node_index: HashMap<i64, u32>,
    /// (file id, node ids, line)
    elems: Vec<(i64, [i64; 4], usize)>,
    elem_index: HashMap<i64, u32>,
    /// (is node set, name) -> [(id, line)]
    sets: BTreeMap<(bool, String), Vec<(i64, usize)>>,
    block: InpBlock,
}

impl InpReader<'_> {
    /// A `*KEYWORD, KEY=VALUE, …` line: the block the data lines that follow belong to.
    fn keyword(&mut self, line_no: usize, kw: &str) -> Result<(), FemError> {
        let at = &self.at;
        let mut parts = kw.split(',').map(str::trim);
        let name = parts.next().unwrap_or("").to_ascii_uppercase();
        let mut params: HashMap<String, String> = HashMap::new();
        for p in parts.filter(|p| !p.is_empty()) {
            let (key, value) = p.split_once('=').unwrap_or((p, ""));
            params.insert(key.trim().to_ascii_uppercase(), value.trim().to_string());
        }
        self.block = match name.as_str() {
            "NODE" => InpBlock::Node,
            "ELEMENT" => {
                let ty = params.get("TYPE").map(|t| t.to_ascii_uppercase());
                match ty {
                    Some(t) if INP_SHELLS.contains(&t.as_str()) => InpBlock::Element {
                        elset: params.get("ELSET").cloned(),
                    },
                    Some(t) => {
                        return Err(at.err(
                            line_no,
                            format!(
                                "*ELEMENT TYPE={t} is not a 4-node shell; use one of {}",
                                INP_SHELLS.join(", ")
                            ),
                        ));
                    }
                    None => return Err(at.err(line_no, "*ELEMENT without TYPE=")),
                }
            }
            "NSET" | "ELSET" => {
                let node = name == "NSET";
                let key = if node { "NSET" } else { "ELSET" };
                let Some(set) = params.get(key).filter(|s| !s.is_empty()) else {
                    return Err(at.err(line_no, format!("*{name} without {key}=")));
                };
                InpBlock::Set {
                    node,
                    name: set.clone(),
                    generate: params.contains_key("GENERATE"),
                }
            }
            _ => InpBlock::Skip,
        };
        if let InpBlock::Set { node, name, .. } = &self.block {
            self.sets.entry((*node, name.clone())).or_default();
        }
        Ok(())
    }

    fn int(&self, line_no: usize, s: &str, what: &str) -> Result<i64, FemError> {
        s.parse::<i64>().map_err(|_| {
            self.at
                .err(line_no, format!("{what} `{s}` is not an integer"))
        })
    }

    /// A data line of the current block.
    fn data(&mut self, line_no: usize, fields: &[&str]) -> Result<(), FemError> {
        match &self.block {
            InpBlock::None => Err(self.at.err(line_no, "data line before any keyword")),
            InpBlock::Skip => Ok(()),
            InpBlock::Node => self.node(line_no, fields),
            InpBlock::Element { elset } => {
                let elset = elset.clone();
                self.element(line_no, fields, elset)
            }
            InpBlock::Set {
                node,
                name,
                generate,
            } => {
                let ids = if *generate {
                    self.generated(line_no, fields)?
                } else {
                    fields
                        .iter()
                        .map(|f| self.int(line_no, f, "id (set references are not supported)"))
                        .collect::<Result<Vec<_>, _>>()?
                };
                let list = self.sets.entry((*node, name.clone())).or_default();
                list.extend(ids.into_iter().map(|i| (i, line_no)));
                Ok(())
            }
        }
    }

    /// `id, x, y[, z]`.
    fn node(&mut self, line_no: usize, fields: &[&str]) -> Result<(), FemError> {
        let at = &self.at;
        if fields.len() < 3 {
            return Err(at.err(line_no, "a *NODE line needs `id, x, y[, z]`"));
        }
        let id = self.int(line_no, fields[0], "node id")?;
        let mut p = Vec3::zeros();
        for (a, f) in fields[1..fields.len().min(4)].iter().enumerate() {
            p[a] = f.parse::<f64>().map_err(|_| {
                at.err(
                    line_no,
                    format!("node {id}: coordinate `{f}` is not a number"),
                )
            })?;
            if !p[a].is_finite() {
                return Err(at.err(
                    line_no,
                    format!("node {id}: coordinate `{f}` is not finite"),
                ));
            }
        }
        if self
            .node_index
            .insert(id, self.nodes.len() as u32)
            .is_some()
        {
            return Err(at.err(line_no, format!("node id {id} is defined twice")));
        }
        self.nodes.push(p);
        self.node_ids.push(id);
        Ok(())
    }

    /// `id, n1, n2, n3, n4`, added to `elset` when the block names one.
    fn element(
        &mut self,
        line_no: usize,
        fields: &[&str],
        elset: Option<String>,
    ) -> Result<(), FemError> {
        if fields.len() != 5 {
            return Err(self.at.err(
                line_no,
                format!(
                    "a 4-node shell line needs `id, n1, n2, n3, n4`, found {} fields",
                    fields.len()
                ),
            ));
        }
        let id = self.int(line_no, fields[0], "element id")?;
        let mut conn = [0i64; 4];
        for (c, f) in conn.iter_mut().zip(&fields[1..]) {
            *c = self.int(line_no, f, "node id")?;
        }
        if self
            .elem_index
            .insert(id, self.elems.len() as u32)
            .is_some()
        {
            return Err(self
                .at
                .err(line_no, format!("element id {id} is defined twice")));
        }
        self.elems.push((id, conn, line_no));
        if let Some(name) = elset {
            self.sets
                .entry((false, name))
                .or_default()
                .push((id, line_no));
        }
        Ok(())
    }

    /// The ids of a `GENERATE` line, `first, last[, step]`.
    fn generated(&self, line_no: usize, fields: &[&str]) -> Result<Vec<i64>, FemError> {
        if !(2..=3).contains(&fields.len()) {
            return Err(self
                .at
                .err(line_no, "a GENERATE line needs `first, last[, step]`"));
        }
        let a = self.int(line_no, fields[0], "first id")?;
        let b = self.int(line_no, fields[1], "last id")?;
        let s = if fields.len() == 3 {
            self.int(line_no, fields[2], "step")?
        } else {
            1
        };
        if s <= 0 || b < a {
            return Err(self.at.err(
                line_no,
                format!("GENERATE {a}, {b}, {s}: need last >= first and step > 0"),
            ));
        }
        let mut ids = Vec::new();
        let mut i = a;
        while i <= b {
            ids.push(i);
            i += s;
        }
        Ok(ids)
    }

    /// The mesh: elements and sets resolved to indices, `all` sets added.
    fn finish(self) -> Result<MeshFile, FemError> {
        let at = &self.at;
        let mut quads = Vec::with_capacity(self.elems.len());
        for (id, conn, line) in &self.elems {
            let mut q = [0u32; 4];
            for (qi, c) in q.iter_mut().zip(conn) {
                *qi = *self.node_index.get(c).ok_or_else(|| {
                    at.err(*line, format!("element {id}: node id {c} is not defined"))
                })?;
            }
            quads.push(q);
        }
        let mut mesh = Mesh {
            nodes: self.nodes,
            quads,
            ..Default::default()
        };
        for ((is_node, name), ids) in self.sets {
            let (index, what) = if is_node {
                (&self.node_index, "node")
            } else {
                (&self.elem_index, "element")
            };
            let mut list = Vec::with_capacity(ids.len());
            for (id, line) in ids {
                list.push(*index.get(&id).ok_or_else(|| {
                    at.err(line, format!("set `{name}`: {what} id {id} is not defined"))
                })?);
            }
            list.sort_unstable();
            list.dedup();
            if is_node {
                mesh.node_sets.insert(name, list);
            } else {
                mesh.element_sets.insert(name, list);
            }
        }
        add_missing_all(&mut mesh);
        Ok(MeshFile {
            mesh,
            node_ids: self.node_ids,
            element_ids: self.elems.iter().map(|e| e.0).collect(),
        })
    }
}

fn add_missing_all(mesh: &mut Mesh) {
    let n = mesh.nodes.len() as u32;
    let e = mesh.quads.len() as u32;
    mesh.node_sets
        .entry("all".into())
        .or_insert_with(|| (0..n).collect());
    mesh.element_sets
        .entry("all".into())
        .or_insert_with(|| (0..e).collect());
}

// ----- Gmsh 4.1 ASCII .msh -------------------------------------------------
//
// Read by hand: the `mshio` crate (0.4.2, ASCII and binary) panics on
// malformed headers (`4.1 0 99999999999999999999999`:
// an unwrap; binary `4.1 1 3`: unimplemented!; `$Nodes` with numNodes 0: an
// overflow in debug builds), and does not read `$PhysicalNames`.

/// Lines of a file with their 1-based numbers, blank lines skipped.
struct Lines<'a> {
    it: std::iter::Peekable<std::iter::Enumerate<std::str::Lines<'a>>>,
    at: At<'a>,
    last: usize,
}

impl<'a> Lines<'a> {
    fn next_line(&mut self) -> Result<(usize, &'a str), FemError> {
        for (k, l) in self.it.by_ref() {
            self.last = k + 1;
            let l = l.trim();
            if !l.is_empty() {
                return Ok((k + 1, l));
            }
        }
        Err(self.at.err(self.last, "unexpected end of file"))
    }

    fn numbers<T: std::str::FromStr>(
        &mut self,
        want: usize,
        what: &str,
    ) -> Result<(usize, Vec<T>), FemError> {
        let (n, l) = self.next_line()?;
        let v: Result<Vec<T>, _> = l.split_whitespace().map(str::parse::<T>).collect();
        match v {
            Ok(v) if v.len() >= want => Ok((n, v)),
            _ => Err(self
                .at
                .err(n, format!("expected {what} ({want} numbers), found `{l}`"))),
        }
    }
}

/// Read a Gmsh 4.1 ASCII `.msh` file: 4-node quads (type 3) of the surface
/// entities become elements; physical groups become sets: a surface group
/// becomes an element set and a node set of its quads' nodes, a curve or
/// point group a node set of the nodes of its elements (names from
/// `$PhysicalNames`, else `dim:tag`). Triangles or higher-order surface
/// elements are an error; volumes are ignored. `all` sets are added. Errors
/// name the file and line. The mesh is not validated here: call
/// [`Mesh::validate`].
pub fn read_msh(path: impl AsRef<Path>) -> Result<Mesh, FemError> {
    read_msh_numbered(path).map(|f| f.mesh)
}

/// [`read_msh`], keeping the file's node and element tags (for messages).
pub fn read_msh_numbered(path: impl AsRef<Path>) -> Result<MeshFile, FemError> {
    let path = path.as_ref();
    let text = read_text(path)?;
    let file = path.display().to_string();
    parse_msh_numbered(&text, &file)
}

#[cfg(test)]
fn parse_msh(text: &str, file: &str) -> Result<Mesh, FemError> {
    parse_msh_numbered(text, file).map(|f| f.mesh)
}

fn parse_msh_numbered(text: &str, file: &str) -> Result<MeshFile, FemError> {
    let mut r = MshReader {
        ls: Lines {
            it: text.lines().enumerate().peekable(),
            at: At { file },
            last: 0,
        },
        names: HashMap::new(),
        ent_phys: HashMap::new(),
        nodes: Vec::new(),
        node_ids: Vec::new(),
        node_index: HashMap::new(),
        quads_raw: Vec::new(),
        ent_nodes: HashMap::new(),
    };
    let mut seen_format = false;
    while let Ok((_, l)) = r.ls.next_line() {
        let end = match l {
            "$MeshFormat" => {
                r.format()?;
                seen_format = true;
                "$EndMeshFormat"
            }
            "$PhysicalNames" => {
                r.physical_names()?;
                "$EndPhysicalNames"
            }
            "$Entities" => {
                r.entities()?;
                "$EndEntities"
            }
            "$Nodes" => {
                r.nodes()?;
                "$EndNodes"
            }
            "$Elements" => {
                r.elements()?;
                "$EndElements"
            }
            s if s.starts_with('$') && !s.starts_with("$End") => {
                // Unknown section: skip to its end.
                let end = format!("$End{}", &s[1..]);
                loop {
                    let (_, l2) = r.ls.next_line()?;
                    if l2 == end {
                        break;
                    }
                }
                continue;
            }
            _ => continue,
        };
        // A section read by its counts ends here: a file cut short (or a
        // count too small) is an error, not a smaller mesh.
        let (n, l2) = r.ls.next_line()?;
        if l2 != end {
            return Err(r.ls.at.err(
                n,
                format!("expected `{end}` after the counted lines, found `{l2}`"),
            ));
        }
    }
    if !seen_format {
        return Err(r
            .ls
            .at
            .err(1, "no $MeshFormat section: not a Gmsh .msh file"));
    }
    r.finish()
}

/// The state of a Gmsh 4.1 file read section by section.
struct MshReader<'a> {
    ls: Lines<'a>,
    names: HashMap<(i32, i32), String>,
    /// (dim, entity tag) -> physical tags
    ent_phys: HashMap<(i32, i32), Vec<i32>>,
    nodes: Vec<Vec3>,
    node_ids: Vec<i64>,
    node_index: HashMap<u64, u32>,
    /// quads (file node tags) with line numbers, entity tag and element tag
    quads_raw: Vec<([u64; 4], usize, i32, u64)>,
    /// (dim, entity) -> node tags of lower-dimensional elements
    ent_nodes: HashMap<(i32, i32), Vec<(u64, usize)>>,
}

impl MshReader<'_> {
    /// `$MeshFormat`: only `4.1 0 8` (ASCII).
    fn format(&mut self) -> Result<(), FemError> {
        let (n2, l2) = self.ls.next_line()?;
        let f: Vec<&str> = l2.split_whitespace().collect();
        if f.len() < 2 || !f[0].starts_with("4.1") || f[1] != "0" {
            return Err(self.ls.at.err(
                n2,
                format!("need Gmsh format `4.1 0 8` (ASCII), found `{l2}`"),
            ));
        }
        Ok(())
    }

    /// `$PhysicalNames`: `dim tag "name"` lines.
    fn physical_names(&mut self) -> Result<(), FemError> {
        let (_, c) = self
            .ls
            .numbers::<usize>(1, "the number of physical names")?;
        for _ in 0..c[0] {
            let (n2, l2) = self.ls.next_line()?;
            let mut it = l2.splitn(3, char::is_whitespace);
            let dim = it.next().and_then(|s| s.parse::<i32>().ok());
            let tag = it.next().and_then(|s| s.parse::<i32>().ok());
            let name = it.next().map(|s| s.trim().trim_matches('"').to_string());
            match (dim, tag, name) {
                (Some(d), Some(t), Some(nm)) => {
                    self.names.insert((d, t), nm);
                }
                _ => {
                    return Err(self
                        .ls
                        .at
                        .err(n2, format!("expected `dim tag \"name\"`, found `{l2}`")));
                }
            }
        }
        Ok(())
    }

    /// `$Entities`: each entity's physical tags.
    fn entities(&mut self) -> Result<(), FemError> {
        let (_, c) = self
            .ls
            .numbers::<usize>(4, "numPoints numCurves numSurfaces numVolumes")?;
        for (dim, &count) in c.iter().take(4).enumerate() {
            for _ in 0..count {
                let (n2, v) = self
                    .ls
                    .numbers::<f64>(if dim == 0 { 5 } else { 8 }, "an entity")?;
                let k = if dim == 0 { 4 } else { 7 };
                // Saturating: a huge or negative count fails the length test.
                let np = v[k] as usize;
                if np > v.len() - (k + 1) {
                    return Err(self
                        .ls
                        .at
                        .err(n2, "entity line shorter than its physical tags"));
                }
                let phys = v[k + 1..k + 1 + np].iter().map(|&t| t as i32).collect();
                self.ent_phys.insert((dim as i32, v[0] as i32), phys);
            }
        }
        Ok(())
    }

    /// A block's count of nodes or elements, refused when negative.
    fn count(&self, line: usize, value: i64, what: &str) -> Result<usize, FemError> {
        usize::try_from(value).map_err(|_| {
            self.ls
                .at
                .err(line, format!("{what} = {value} is negative"))
        })
    }

    /// `$Nodes`: blocks of tags, then their coordinates.
    fn nodes(&mut self) -> Result<(), FemError> {
        let (_, h) = self
            .ls
            .numbers::<u64>(4, "numEntityBlocks numNodes minNodeTag maxNodeTag")?;
        for _ in 0..h[0] {
            let (n2, b) = self
                .ls
                .numbers::<i64>(4, "entityDim entityTag parametric numNodesInBlock")?;
            let count = self.count(n2, b[3], "numNodesInBlock")?;
            // Not reserved by the file's count: a wrong one must not exhaust memory.
            let mut tags = Vec::new();
            for _ in 0..count {
                let (_, t) = self.ls.numbers::<u64>(1, "a node tag")?;
                tags.push(t[0]);
            }
            for tag in tags {
                let (n3, p) = self.ls.numbers::<f64>(3, "node coordinates x y z")?;
                if !p[..3].iter().all(|c| c.is_finite()) {
                    return Err(self
                        .ls
                        .at
                        .err(n3, format!("node {tag}: coordinates are not finite")));
                }
                if self
                    .node_index
                    .insert(tag, self.nodes.len() as u32)
                    .is_some()
                {
                    return Err(self
                        .ls
                        .at
                        .err(n3, format!("node tag {tag} is defined twice")));
                }
                self.nodes.push(Vec3::new(p[0], p[1], p[2]));
                self.node_ids.push(tag as i64);
            }
        }
        Ok(())
    }

    /// `$Elements`: quads on surfaces, the nodes of points and curves.
    fn elements(&mut self) -> Result<(), FemError> {
        let (_, h) = self
            .ls
            .numbers::<u64>(4, "numEntityBlocks numElements minElementTag maxElementTag")?;
        for _ in 0..h[0] {
            let (n2, b) = self
                .ls
                .numbers::<i64>(4, "entityDim entityTag elementType numElementsInBlock")?;
            let (dim, ent, ty) = (b[0] as i32, b[1] as i32, b[2]);
            let count = self.count(n2, b[3], "numElementsInBlock")?;
            if dim == 2 && ty != 3 {
                return Err(self.ls.at.err(
                    n2,
                    format!("surface {ent}: element type {ty} is not a 4-node quad (type 3); mesh with quads (Recombine)"),
                ));
            }
            for _ in 0..count {
                let (n3, e) = self.ls.numbers::<u64>(2, "an element line")?;
                if dim == 2 {
                    if e.len() != 5 {
                        return Err(self
                            .ls
                            .at
                            .err(n3, format!("element {}: a quad needs 4 node tags", e[0])));
                    }
                    self.quads_raw
                        .push(([e[1], e[2], e[3], e[4]], n3, ent, e[0]));
                } else if dim < 2 {
                    let list = self.ent_nodes.entry((dim, ent)).or_default();
                    list.extend(e[1..].iter().map(|&t| (t, n3)));
                }
            }
        }
        Ok(())
    }

    /// The mesh: quads and physical groups resolved to indices, `all` sets added.
    fn finish(self) -> Result<MeshFile, FemError> {
        let MshReader {
            ls,
            names,
            ent_phys,
            nodes,
            node_ids,
            node_index,
            quads_raw,
            ent_nodes,
        } = self;
        let resolve = |tag: u64, line: usize| -> Result<u32, FemError> {
            node_index
                .get(&tag)
                .copied()
                .ok_or_else(|| ls.at.err(line, format!("node tag {tag} is not defined")))
        };
        let group_name = |dim: i32, tag: i32| {
            names
                .get(&(dim, tag))
                .cloned()
                .unwrap_or_else(|| format!("{dim}:{tag}"))
        };
        let mut mesh = Mesh {
            nodes,
            ..Default::default()
        };
        for (e, (conn, line, ent, _)) in quads_raw.iter().enumerate() {
            let mut q = [0u32; 4];
            for (qi, &c) in q.iter_mut().zip(conn) {
                *qi = resolve(c, *line)?;
            }
            mesh.quads.push(q);
            for &p in ent_phys.get(&(2, *ent)).into_iter().flatten() {
                let name = group_name(2, p);
                mesh.element_sets
                    .entry(name.clone())
                    .or_default()
                    .push(e as u32);
                mesh.node_sets
                    .entry(name)
                    .or_default()
                    .extend_from_slice(&q);
            }
        }
        for (&(dim, ent), list) in &ent_nodes {
            for &p in ent_phys.get(&(dim, ent)).into_iter().flatten() {
                let name = group_name(dim, p);
                for &(tag, line) in list {
                    let i = resolve(tag, line)?;
                    mesh.node_sets.entry(name.clone()).or_default().push(i);
                }
            }
        }
        for set in mesh
            .node_sets
            .values_mut()
            .chain(mesh.element_sets.values_mut())
        {
            set.sort_unstable();
            set.dedup();
        }
        add_missing_all(&mut mesh);
        Ok(MeshFile {
            mesh,
            node_ids,
            element_ids: quads_raw.iter().map(|q| q.3 as i64).collect(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const INP: &str = "\
** a 2 x 1 strip
*Heading
strip
*NODE
 10, 0.0, 0.0, 0.0
 11, 1.0, 0.0, 0.0
 12, 2.0, 0.0, 0.0
 20, 0.0, 1.0, 0.0
 21, 1.0, 1.0
 22, 2.0, 1.0, 0.0
*ELEMENT, TYPE=S4R, ELSET=SHELL
 1, 10, 11, 21, 20
 2, 11, 12, 22, 21
*NSET, NSET=LEFT
 10, 20
*NSET, NSET=BOTTOM, GENERATE
 10, 12, 1
*ELSET, ELSET=FIRST
 1
";

    #[test]
    fn inp_reads_nodes_quads_and_sets() {
        let m = parse_inp(INP, "strip.inp").unwrap();
        assert_eq!(m.nodes.len(), 6);
        assert_eq!(m.quads, vec![[0, 1, 4, 3], [1, 2, 5, 4]]);
        assert_eq!(m.node_sets["LEFT"], vec![0, 3]);
        assert_eq!(m.node_sets["BOTTOM"], vec![0, 1, 2]);
        assert_eq!(m.element_sets["SHELL"], vec![0, 1]);
        assert_eq!(m.element_sets["FIRST"], vec![0]);
        assert_eq!(m.node_sets["all"].len(), 6);
        assert_eq!(m.nodes[4], Vec3::new(1.0, 1.0, 0.0));
        m.validate().unwrap();
    }

    #[test]
    fn numbered_readers_keep_the_file_ids() {
        let f = parse_inp_numbered(INP, "strip.inp").unwrap();
        assert_eq!(f.node_ids, [10, 11, 12, 20, 21, 22]);
        assert_eq!(f.element_ids, [1, 2]);
        assert_eq!(f.mesh, parse_inp(INP, "strip.inp").unwrap());
        let f = parse_msh_numbered(MSH, "plate.msh").unwrap();
        assert_eq!(f.node_ids, [1, 4, 2, 3, 5, 6]);
        assert_eq!(f.element_ids, [2, 3]);
    }

    #[test]
    fn inp_undefined_node_names_file_and_line() {
        let bad = INP.replace(" 2, 11, 12, 22, 21", " 2, 11, 12, 99, 21");
        let e = parse_inp(&bad, "strip.inp").unwrap_err();
        assert_eq!(
            e.to_string(),
            "strip.inp:13: element 2: node id 99 is not defined"
        );
    }

    #[test]
    fn inp_bad_number_and_type_name_file_and_line() {
        let bad = INP.replace(" 11, 1.0, 0.0, 0.0", " 11, 1.0, x, 0.0");
        let e = parse_inp(&bad, "s.inp").unwrap_err().to_string();
        assert!(e.starts_with("s.inp:6: node 11: coordinate `x`"), "{e}");
        let bad = INP.replace("TYPE=S4R", "TYPE=S3");
        let e = parse_inp(&bad, "s.inp").unwrap_err().to_string();
        assert!(
            e.starts_with("s.inp:11: *ELEMENT TYPE=S3 is not a 4-node shell"),
            "{e}"
        );
        let bad = INP.replace(" 10, 20\n", " 10, 77\n");
        let e = parse_inp(&bad, "s.inp").unwrap_err().to_string();
        assert_eq!(e, "s.inp:15: set `LEFT`: node id 77 is not defined");
    }

    #[test]
    fn inp_and_msh_files_read_from_disk() {
        let dir = std::env::temp_dir().join(format!("fem-core-io-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let inp = dir.join("strip.inp");
        std::fs::write(&inp, INP).unwrap();
        assert_eq!(read_inp(&inp).unwrap(), parse_inp(INP, "x").unwrap());
        let msh = dir.join("plate.msh");
        std::fs::write(&msh, MSH).unwrap();
        assert_eq!(read_msh(&msh).unwrap().quads.len(), 2);
        let bad = dir.join("bad.inp");
        std::fs::write(&bad, INP.replace(" 1, 10, 11, 21, 20", " 1, 10, 11, 21")).unwrap();
        let e = read_inp(&bad).unwrap_err().to_string();
        assert_eq!(
            e,
            format!(
                "{}:12: a 4-node shell line needs `id, n1, n2, n3, n4`, found 4 fields",
                bad.display()
            )
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn inp_missing_file_is_an_error() {
        let e = read_inp("/nonexistent/dir/mesh.inp")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("/nonexistent/dir/mesh.inp:0: cannot read the file"),
            "{e}"
        );
    }

    const MSH: &str = "\
$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
1 1 \"clamped\"
2 2 \"plate\"
$EndPhysicalNames
$Entities
0 1 1 0
1 0 0 0 0 1 0 1 1 2 0 0
1 0 0 0 2 1 0 1 2 0
$EndEntities
$Nodes
2 6 1 6
1 1 0 2
1
4
0 0 0
0 1 0
2 1 0 4
2
3
5
6
1 0 0
2 0 0
1 1 0
2 1 0
$EndNodes
$Elements
2 3 1 3
1 1 1 1
1 1 4
2 1 3 2
2 1 2 5 4
3 2 3 6 5
$EndElements
";

    #[test]
    fn msh_reads_quads_and_physical_groups() {
        let m = parse_msh(MSH, "plate.msh").unwrap();
        assert_eq!(m.nodes.len(), 6);
        assert_eq!(m.quads, vec![[0, 2, 4, 1], [2, 3, 5, 4]]);
        assert_eq!(m.node_sets["clamped"], vec![0, 1]);
        assert_eq!(m.element_sets["plate"], vec![0, 1]);
        assert_eq!(m.node_sets["plate"].len(), 6);
        m.validate().unwrap();
    }

    #[test]
    fn msh_errors_name_file_and_line() {
        let bad = MSH.replace("3 2 3 6 5", "3 2 3 6 99");
        let e = parse_msh(&bad, "p.msh").unwrap_err().to_string();
        assert_eq!(e, "p.msh:37: node tag 99 is not defined");
        let bad = MSH.replace("2 1 3 2\n", "2 1 2 2\n");
        let e = parse_msh(&bad, "p.msh").unwrap_err().to_string();
        assert!(e.starts_with("p.msh:35: surface 1: element type 2"), "{e}");
        let bad = MSH.replace("4.1 0 8", "2.2 0 8");
        let e = parse_msh(&bad, "p.msh").unwrap_err().to_string();
        assert!(e.starts_with("p.msh:2: need Gmsh format"), "{e}");
    }

    /// Every prefix of a valid file is an error unless it ends with a whole
    /// section, and no changed byte or wild count makes the reader panic or
    /// reserve memory by the file's word.
    #[test]
    fn msh_truncated_or_garbled_files_are_errors_not_panics() {
        let ends = [
            "$EndMeshFormat",
            "$EndPhysicalNames",
            "$EndEntities",
            "$EndNodes",
            "$EndElements",
        ];
        for n in 0..MSH.len() {
            let prefix = &MSH[..n];
            let whole_sections = ends.iter().any(|e| prefix.trim_end().ends_with(e));
            match parse_msh(prefix, "p.msh") {
                Ok(m) => assert!(whole_sections, "prefix {n} read: {m:?}"),
                Err(e) => assert!(e.to_string().starts_with("p.msh:"), "{e}"),
            }
            for c in ['x', '9', '-', ' ', '\n', '$', '0'] {
                let mut g = MSH.to_string();
                g.replace_range(n..n + 1, &c.to_string());
                let _ = parse_msh(&g, "p.msh");
            }
        }
        for (from, to, message) in [
            (
                "2 1 0 4\n",
                "2 1 0 99999999999999999\n",
                "p.msh:30: expected a node tag",
            ),
            (
                "2 1 0 4\n",
                "2 1 0 -4\n",
                "p.msh:21: numNodesInBlock = -4 is negative",
            ),
            (
                "2 1 3 2\n",
                "2 1 3 -2\n",
                "p.msh:35: numElementsInBlock = -2 is negative",
            ),
            (
                "2 1 3 2\n",
                "2 1 3 1\n",
                "p.msh:37: expected `$EndElements`",
            ),
            (
                "$PhysicalNames\n2\n",
                "$PhysicalNames\n99999999999999999\n",
                "p.msh:8: expected `dim tag",
            ),
            (
                "1 0 0 0 2 1 0 1 2 0\n",
                "1 0 0 0 2 1 0 1e300 2 0\n",
                "p.msh:12: entity line shorter",
            ),
        ] {
            let bad = MSH.replace(from, to);
            assert_ne!(bad, MSH, "{from:?}");
            let e = parse_msh(&bad, "p.msh").unwrap_err().to_string();
            assert!(e.starts_with(message), "{to:?}: {e}");
        }
    }
}
