//! The sparse factorisations of a springback tangent on `faer`: which
//! settings matter for the static solver (`fem_core::statics`, whose
//! `factor.rs` makes an AMD Cholesky analysis, LU with faer's default
//! COLAMD analysis for the unsymmetric shell tangent, all `Par::Seq`).
//!
//! The matrix is the first tangent of a springback release, built as the
//! springback step builds it: a quarter blank (100 × 100 mm, 50 × 50
//! Belytschko–Tsay shells, 0.78 mm, five Gauss points, the square cup's
//! Hill'48 steel) stretched by 1 % along x and 0.5 % along y and domed to
//! a curvature of 0.001 1/mm (10 mm of sag) by 40 explicit steps, every
//! point plastic; taken over by `StaticShells::from_shell_set` into a
//! stress release with the quarter's symmetry planes (x = 0, y = 0) and
//! `uz` of the centre node fixed; assembled by
//! `StaticSolver::tangent_matrix`. It has the square cup's size: 15,300
//! equations, 801,882 stored entries. Its symmetric part `S = (K + Kᵀ)/2`
//! is positive definite here (stretched and domed twice as far, 2 % and
//! 20 mm, it has six negative pivots).
//!
//! Measured on it, each timed call one factorisation or solve:
//! - the symbolic analyses (AMD Cholesky, COLAMD LU);
//! - numeric LU of `K`: faer's analysis (COLAMD), supernodal (its
//!   automatic choice) and simplicial; the supernodal analysis on a given
//!   column ordering (AMD of the symmetric pattern, as the Cholesky's; a
//!   nested dissection), through faer's public supernodal LU functions;
//! - numeric `LLᵀ` and `LDLᵀ` of `S`: supernodal (the automatic choice)
//!   and simplicial, orderings AMD, identity (the mesh's own row-by-row
//!   numbering, a band) and a geometric nested dissection of the node grid
//!   (`SymmetricOrdering::Custom`);
//! - `Par::Seq` against `Par::rayon(2)` for the supernodal factorisations;
//! - the solve of one right-hand side (the start state's internal forces,
//!   which the release lets go);
//! - a Newton iteration's whole linear solve `K x = b`: LU, against `LLᵀ`
//!   of `S` with iterative refinement on `K` to `‖b − K x‖ ≤ 1e-10 ‖b‖`.
//!
//! Before the timings it prints the residuals of the solves and the rate
//! at which Newton's iteration with `S` in place of `K` contracts the
//! error, `ρ(S⁻¹ (S − K))`. At the end a table gives, per setting, the
//! factor's size and the fastest and median time over the measured calls
//! (warm-up excluded): the fastest is the robust estimate on a shared
//! machine, whose load only ever adds time. The settings that take
//! seconds (simplicial LU) are timed over two or three calls outside
//! criterion. Factor size: stored values of `L` for Cholesky; `|L| + |U|`
//! for the simplicial LU (exact); for the supernodal LU, whose size faer
//! does not give, the bound `2 |R| − n` (`R` the Cholesky factor of `AᵀA`
//! under the column ordering, the structure its analysis works on); and
//! the bytes the analysis and the factor hold (scratch excluded), counted
//! by the allocator.
//!
//! Run: `cargo bench -p shell-elements --bench static_factor` (about a
//! minute on an idle 2-core machine); `-- numeric/llt` and the like run a
//! subset, and the table lists what ran.

use criterion::{Criterion, SamplingMode};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LdltRef, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::linalg::lu::simplicial::{
    SimplicialLu, factorize_simplicial_numeric_lu, factorize_simplicial_numeric_lu_scratch,
};
use faer::sparse::linalg::lu::supernodal::{
    SupernodalLu, SymbolicSupernodalLu, factorize_supernodal_numeric_lu,
    factorize_supernodal_numeric_lu_scratch, factorize_supernodal_symbolic_lu,
    factorize_supernodal_symbolic_lu_scratch,
};
use faer::sparse::linalg::lu::{
    LuRef, LuSymbolicParams, NumericLu, SymbolicLu, factorize_symbolic_lu,
};
use faer::sparse::linalg::qr::{
    col_etree, col_etree_scratch, column_counts_aat_scratch, column_counts_ata, postorder,
    postorder_scratch,
};
use faer::sparse::utils::{transpose, transpose_scratch};
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use fem_core::statics::{NewtonSettings, StaticProblem, StaticSolver, TrialState, dense_tangent};
use fem_core::{Dof, Dofs, Effect, FieldAccess, Forces, Mat3, NodalState, StepContext, Vec3};
use shell_elements::material::Hill48PlaneStress;
use shell_elements::{BelytschkoTsay, Hardening, Section, ShellSet, StaticShells};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicIsize, Ordering};
use std::time::{Duration, Instant};

/// The system allocator, counting the bytes live.
struct Counting;

static LIVE: AtomicIsize = AtomicIsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LIVE.fetch_add(layout.size() as isize, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        LIVE.fetch_add(layout.size() as isize, Ordering::Relaxed);
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size() as isize, Ordering::Relaxed);
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LIVE.fetch_add(
            new_size as isize - layout.size() as isize,
            Ordering::Relaxed,
        );
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// `f()` and the bytes it left allocated.
fn counted<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let before = LIVE.load(Ordering::Relaxed);
    let value = f();
    let after = LIVE.load(Ordering::Relaxed);
    (value, (after - before).max(0) as usize)
}

/// Shells per side of the quarter blank.
const CELLS: usize = 50;
/// Side of the quarter blank (mm).
const SIDE: f64 = 100.0;

/// The springback release of the stretched and domed quarter blank (see
/// the file's docs).
fn release() -> StaticSolver {
    let mesh = fem_core::rectangle(SIDE, SIDE, CELLS, CELLS).unwrap();
    let steel = Hill48PlaneStress::new(
        206_000.0,
        0.3,
        7.85e-9,
        Hardening::swift(565.32, 0.007117, 0.2589).unwrap(),
        [1.79, 1.51, 2.27],
    )
    .unwrap();
    let section = Section::new(0.78).unwrap();
    let mut set = ShellSet::new(
        "blank",
        &mesh.nodes,
        &mesh.quads,
        section,
        BelytschkoTsay::default(),
        steel,
    )
    .unwrap();
    // 40 steps of 5e-4 s: a biaxial stretch (1 : 0.5) at 0.5 /s and a
    // dome about the centre node (0, 0) at curvature rate 0.05 1/(mm s),
    // the normal velocity following the rotation rates.
    let (steps, dt, stretch, bend) = (40, 5e-4, 0.5, 0.05);
    let mut st = NodalState::at_rest(&mesh.nodes);
    for (i, p) in mesh.nodes.iter().enumerate() {
        st.v[i] = Vec3::new(
            stretch * p.x,
            0.5 * stretch * p.y,
            -0.5 * bend * (p.x * p.x + p.y * p.y),
        );
        st.w[i] = Vec3::new(-bend * p.y, bend * p.x, 0.0);
    }
    let mut forces = Forces::zeros(mesh.nodes.len());
    for step in 1..=steps {
        for (x, v) in st.x.iter_mut().zip(&st.v) {
            *x += dt * v;
        }
        let ctx = StepContext {
            time: step as f64 * dt,
            dt,
            step,
            press: None,
        };
        forces.clear();
        set.add_forces(&ctx, &st, &mut forces, &mut FieldAccess::none())
            .unwrap();
    }
    let points = set.len() * set.points_per_element();
    let plastic = (0..set.len())
        .flat_map(|e| (0..set.points_per_element()).map(move |k| (e, k)))
        .filter(|&(e, k)| set.plastic_strain(e, 0, k) > 0.0)
        .count();
    let eps_max = (0..set.len())
        .flat_map(|e| (0..set.points_per_element()).map(move |k| (e, k)))
        .map(|(e, k)| set.plastic_strain(e, 0, k))
        .fold(0.0, f64::max);
    let sag = st.x.iter().map(|p| -p.z).fold(0.0, f64::max);
    eprintln!(
        "blank: {} shells, sag {sag:.1} mm, {:.0} % of the points plastic, ε_p up to {eps_max:.4}",
        set.len(),
        100.0 * plastic as f64 / points as f64,
    );
    let shells = StaticShells::from_shell_set("blank", &set);
    let mut problem = StaticProblem::new(&st.x).unwrap();
    problem.add_effect(shells);
    problem.release_start_forces();
    let sets = &mesh.node_sets;
    problem
        .fix(&sets["x0"], Dofs::of(&[Dof::Ux, Dof::Ry, Dof::Rz]))
        .unwrap();
    problem
        .fix(&sets["y0"], Dofs::of(&[Dof::Uy, Dof::Rx, Dof::Rz]))
        .unwrap();
    problem.fix(&[0], Dofs::of(&[Dof::Uz])).unwrap();
    StaticSolver::new(problem, NewtonSettings::default()).unwrap()
}

/// For every stored entry `p` of column `j`, row `i`, the index of the
/// entry (`j`, `i`); the pattern is structurally symmetric.
fn transposed_index(a: SymbolicSparseColMatRef<'_, usize>) -> Vec<usize> {
    let (col_ptr, row_idx) = (a.col_ptr(), a.row_idx());
    let mut t = vec![0; row_idx.len()];
    for j in 0..a.ncols() {
        for p in col_ptr[j]..col_ptr[j + 1] {
            let i = row_idx[p];
            let col = &row_idx[col_ptr[i]..col_ptr[i + 1]];
            t[p] = col_ptr[i] + col.binary_search(&j).expect("a symmetric pattern");
        }
    }
    t
}

/// A nested dissection of the `(CELLS + 1)²` node grid (node `(i, j)` is
/// `j (CELLS + 1) + i`): each block of nodes is split by its middle line
/// across its longer side, the two halves first, the line last; blocks of
/// at most `LEAF` nodes keep the mesh's order.
fn nested_dissection() -> Vec<usize> {
    const LEAF: usize = 16;
    fn split(i: (usize, usize), j: (usize, usize), out: &mut Vec<usize>) {
        let (ni, nj) = (i.1 - i.0, j.1 - j.0);
        if ni == 0 || nj == 0 {
            return;
        }
        if ni * nj <= LEAF || ni.max(nj) < 3 {
            for jj in j.0..j.1 {
                out.extend((i.0..i.1).map(|ii| jj * (CELLS + 1) + ii));
            }
            return;
        }
        if ni >= nj {
            let m = i.0 + ni / 2;
            split((i.0, m), j, out);
            split((m + 1, i.1), j, out);
            split((m, m + 1), j, out);
        } else {
            let m = j.0 + nj / 2;
            split(i, (j.0, m), out);
            split(i, (m + 1, j.1), out);
            split(i, (m, m + 1), out);
        }
    }
    let mut order = Vec::with_capacity((CELLS + 1) * (CELLS + 1));
    split((0, CELLS + 1), (0, CELLS + 1), &mut order);
    order
}

/// A permutation `(fwd, inv)` of the equations: `fwd[k]` is the equation
/// eliminated `k`-th.
struct Perm {
    fwd: Vec<usize>,
    inv: Vec<usize>,
}

impl Perm {
    fn new(fwd: Vec<usize>) -> Self {
        let mut inv = vec![0; fwd.len()];
        for (k, &e) in fwd.iter().enumerate() {
            inv[e] = k;
        }
        Self { fwd, inv }
    }

    fn as_ref(&self) -> PermRef<'_, usize> {
        PermRef::new_checked(&self.fwd, &self.inv, self.fwd.len())
    }
}

/// The nested dissection of the grid's nodes, as an order of the equations.
fn nd_equations(solver: &StaticSolver, n: usize) -> Perm {
    let mut of_node = vec![Vec::new(); (CELLS + 1) * (CELLS + 1)];
    for e in 0..n {
        let (node, _) = solver.equation_dof(e).unwrap();
        of_node[node].push(e);
    }
    let fwd: Vec<usize> = nested_dissection()
        .into_iter()
        .flat_map(|node| of_node[node].iter().copied())
        .collect();
    assert_eq!(fwd.len(), n);
    Perm::new(fwd)
}

/// Which ordering and which factorisation kind.
#[derive(Clone, Copy)]
enum Order<'a> {
    Amd,
    Identity,
    Custom(&'a Perm),
}

fn threshold(supernodal: Option<bool>) -> SupernodalThreshold {
    match supernodal {
        None => SupernodalThreshold::AUTO,
        Some(true) => SupernodalThreshold::FORCE_SUPERNODAL,
        Some(false) => SupernodalThreshold::FORCE_SIMPLICIAL,
    }
}

/// Size of a factor.
#[derive(Clone, Copy)]
enum Nnz {
    Exact(usize),
    Bound(usize),
}

impl std::fmt::Display for Nnz {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let thousands = |v: usize| format!("{:.2} M", v as f64 / 1e6);
        match self {
            Nnz::Exact(v) => write!(f, "{}", thousands(*v)),
            Nnz::Bound(v) => write!(f, "≤ {}", thousands(*v)),
        }
    }
}

/// A factorisation of one matrix, analysed once, factorised and solved
/// again and again.
trait Factor {
    /// One numeric factorisation.
    fn numeric(&mut self);
    /// Solve `A x = b` in place with the last factor.
    fn solve(&mut self, rhs: &mut [f64]);
    /// Size of the factor (after one numeric factorisation).
    fn nnz(&self) -> Nnz;
    /// The kind faer chose or was told to make.
    fn kind(&self) -> &'static str;
    /// Bytes of its scratch buffers (not part of the factor).
    fn scratch(&self) -> usize;
}

/// Cholesky (`LLᵀ` or `LDLᵀ`) on faer's analysis.
struct Cholesky<'a> {
    a: SparseColMatRef<'a, usize, f64>,
    symbolic: SymbolicCholesky<usize>,
    l: Vec<f64>,
    ldlt: bool,
    par: Par,
    mem: (MemBuffer, usize),
}

impl<'a> Cholesky<'a> {
    fn new(
        a: SparseColMatRef<'a, usize, f64>,
        order: Order<'_>,
        supernodal: Option<bool>,
        ldlt: bool,
        par: Par,
    ) -> Self {
        let symbolic = cholesky_symbolic(a.symbolic(), order, supernodal);
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
            symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, par),
        ]);
        Self {
            a,
            l: vec![0.0; symbolic.len_val()],
            symbolic,
            ldlt,
            par,
            mem: counted(|| MemBuffer::new(req)),
        }
    }
}

fn cholesky_symbolic(
    a: SymbolicSparseColMatRef<'_, usize>,
    order: Order<'_>,
    supernodal: Option<bool>,
) -> SymbolicCholesky<usize> {
    let ord = match order {
        Order::Amd => SymmetricOrdering::Amd,
        Order::Identity => SymmetricOrdering::Identity,
        Order::Custom(p) => SymmetricOrdering::Custom(p.as_ref()),
    };
    let params = CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: threshold(supernodal),
        ..Default::default()
    };
    factorize_symbolic_cholesky(a, Side::Lower, ord, params).unwrap()
}

impl Factor for Cholesky<'_> {
    fn numeric(&mut self) {
        let stack = MemStack::new(&mut self.mem.0);
        if self.ldlt {
            self.symbolic
                .factorize_numeric_ldlt(
                    &mut self.l,
                    self.a,
                    Side::Lower,
                    LdltRegularization::default(),
                    self.par,
                    stack,
                    Default::default(),
                )
                .unwrap();
        } else {
            self.symbolic
                .factorize_numeric_llt(
                    &mut self.l,
                    self.a,
                    Side::Lower,
                    LltRegularization::default(),
                    self.par,
                    stack,
                    Default::default(),
                )
                .expect("the symmetric part is positive definite");
        }
    }

    fn solve(&mut self, rhs: &mut [f64]) {
        let n = rhs.len();
        let x = MatMut::from_column_major_slice_mut(rhs, n, 1);
        let stack = MemStack::new(&mut self.mem.0);
        if self.ldlt {
            LdltRef::new(&self.symbolic, &self.l).solve_in_place_with_conj(
                Conj::No,
                x,
                self.par,
                stack,
            );
        } else {
            LltRef::new(&self.symbolic, &self.l).solve_in_place_with_conj(
                Conj::No,
                x,
                self.par,
                stack,
            );
        }
    }

    fn nnz(&self) -> Nnz {
        Nnz::Exact(self.symbolic.len_val())
    }

    fn scratch(&self) -> usize {
        self.mem.1
    }

    fn kind(&self) -> &'static str {
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => "simplicial",
            SymbolicCholeskyRaw::Supernodal(_) => "supernodal",
        }
    }
}

/// The structure of the supernodal LU analysis under a column ordering:
/// the column elimination tree of `A` (of `AᵀA`), the column counts of
/// `AᵀA`'s Cholesky factor `R` and each row's first column.
struct AtaStructure {
    etree: Vec<usize>,
    col_counts: Vec<usize>,
    min_col: Vec<usize>,
}

impl AtaStructure {
    fn new(a: SymbolicSparseColMatRef<'_, usize>, col_perm: PermRef<'_, usize>) -> Self {
        let n = a.ncols();
        let mut mem = MemBuffer::new(StackReq::any_of(&[
            col_etree_scratch::<usize>(n, n),
            postorder_scratch::<usize>(n),
            column_counts_aat_scratch::<usize>(n, n),
            transpose_scratch::<usize>(n, n),
        ]));
        let stack = MemStack::new(&mut mem);
        let (mut etree, mut post) = (vec![0usize; n], vec![0usize; n]);
        let (mut col_counts, mut min_col) = (vec![0usize; n], vec![0usize; n]);
        // The transpose's pattern, for the column counts.
        let zeros = vec![0u8; a.row_idx().len()];
        let ones = SparseColMatRef::new(a, &zeros[..]);
        let (mut t_val, mut t_ptr, mut t_idx) = (
            vec![0u8; a.row_idx().len()],
            vec![0usize; n + 1],
            vec![0usize; a.row_idx().len()],
        );
        let at = transpose(&mut t_val, &mut t_ptr, &mut t_idx, ones, stack);
        let at = at.symbolic();
        let tree = col_etree(a, Some(col_perm), &mut etree, stack);
        postorder(&mut post, tree, stack);
        column_counts_ata(
            &mut col_counts,
            &mut min_col,
            at,
            Some(col_perm),
            tree,
            &post,
            stack,
        );
        Self {
            etree,
            col_counts,
            min_col,
        }
    }

    /// `2 |R| − n`: the bound on `|L| + |U|` the supernodal analysis allocates.
    fn bound(&self) -> usize {
        2 * self.col_counts.iter().sum::<usize>() - self.col_counts.len()
    }

    /// Whether faer's automatic choice (`SupernodalThreshold::AUTO`) is
    /// supernodal: the flops over the nonzeros of the analysis above 40.
    fn auto_supernodal(&self) -> bool {
        let n = self.col_counts.len();
        let mut h = vec![0usize; n];
        for &c in &self.min_col {
            if (c as isize) >= 0 && c < n {
                h[c] += 1;
            }
        }
        for j in 0..n {
            let parent = self.etree[j] as isize;
            if parent >= 0 {
                h[parent as usize] += h[j].saturating_sub(1);
            }
        }
        let (mut nnz, mut flops) = (0.0, 0.0);
        for (hj, rj) in h.iter().zip(&self.col_counts) {
            let (hj, rj) = (*hj as f64, *rj as f64);
            flops += hj + hj * rj;
            nnz += hj + rj;
        }
        flops / nnz > 40.0
    }
}

/// LU on faer's own analysis (COLAMD), as `factor.rs` makes it.
struct FaerLu<'a> {
    a: SparseColMatRef<'a, usize, f64>,
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    supernodal: bool,
    bound: usize,
    par: Par,
    mem: (MemBuffer, usize),
}

impl<'a> FaerLu<'a> {
    fn new(a: SparseColMatRef<'a, usize, f64>, supernodal: Option<bool>, par: Par) -> Self {
        let params = LuSymbolicParams {
            supernodal_flop_ratio_threshold: threshold(supernodal),
            ..Default::default()
        };
        let symbolic = factorize_symbolic_lu(a.symbolic(), params).unwrap();
        let ata = AtaStructure::new(a.symbolic(), symbolic.col_perm());
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_lu_scratch::<f64>(par, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, par),
        ]);
        Self {
            a,
            supernodal: supernodal.unwrap_or_else(|| ata.auto_supernodal()),
            bound: ata.bound(),
            symbolic,
            numeric: NumericLu::new(),
            par,
            mem: counted(|| MemBuffer::new(req)),
        }
    }
}

impl Factor for FaerLu<'_> {
    fn numeric(&mut self) {
        let stack = MemStack::new(&mut self.mem.0);
        self.symbolic
            .factorize_numeric_lu(
                &mut self.numeric,
                self.a,
                self.par,
                stack,
                Default::default(),
            )
            .unwrap();
    }

    fn solve(&mut self, rhs: &mut [f64]) {
        let n = rhs.len();
        let x = MatMut::from_column_major_slice_mut(rhs, n, 1);
        let stack = MemStack::new(&mut self.mem.0);
        LuRef::new_unchecked(&self.symbolic, &self.numeric).solve_in_place_with_conj(
            Conj::No,
            x,
            self.par,
            stack,
        );
    }

    fn nnz(&self) -> Nnz {
        Nnz::Bound(self.bound)
    }

    fn scratch(&self) -> usize {
        self.mem.1
    }

    fn kind(&self) -> &'static str {
        if self.supernodal {
            "supernodal"
        } else {
            "simplicial"
        }
    }
}

/// Supernodal LU on a given column ordering, through faer's public
/// supernodal functions (what `factorize_symbolic_lu` does after COLAMD).
struct OrderedLu<'a> {
    a: SparseColMatRef<'a, usize, f64>,
    col_perm: &'a Perm,
    symbolic: SymbolicSupernodalLu<usize>,
    lu: SupernodalLu<usize, f64>,
    row_perm: Vec<usize>,
    row_perm_inv: Vec<usize>,
    /// `Aᵀ`, made by every factorisation as faer's own path makes it.
    at: (Vec<f64>, Vec<usize>, Vec<usize>),
    bound: usize,
    par: Par,
    mem: (MemBuffer, usize),
}

impl<'a> OrderedLu<'a> {
    fn new(a: SparseColMatRef<'a, usize, f64>, col_perm: &'a Perm, par: Par) -> Self {
        let n = a.ncols();
        let nnz = a.row_idx().len();
        let ata = AtaStructure::new(a.symbolic(), col_perm.as_ref());
        let mut mem = MemBuffer::new(StackReq::any_of(&[
            col_etree_scratch::<usize>(n, n),
            factorize_supernodal_symbolic_lu_scratch::<usize>(n, n),
        ]));
        let stack = MemStack::new(&mut mem);
        let mut etree = vec![0usize; n];
        let tree = col_etree(a.symbolic(), Some(col_perm.as_ref()), &mut etree, stack);
        let symbolic = factorize_supernodal_symbolic_lu(
            a.symbolic(),
            Some(col_perm.as_ref()),
            &ata.min_col,
            tree,
            &ata.col_counts,
            stack,
            Default::default(),
        )
        .unwrap();
        let req = StackReq::any_of(&[
            factorize_supernodal_numeric_lu_scratch::<usize, f64>(&symbolic, Default::default()),
            faer::sparse::linalg::lu::supernodal::solve_in_place_scratch::<usize, f64>(n, 1, par),
            transpose_scratch::<usize>(n, n),
        ]);
        Self {
            a,
            col_perm,
            symbolic,
            lu: SupernodalLu::new(),
            row_perm: vec![0; n],
            row_perm_inv: vec![0; n],
            at: (vec![0.0; nnz], vec![0; n + 1], vec![0; nnz]),
            bound: ata.bound(),
            par,
            mem: counted(|| MemBuffer::new(req)),
        }
    }
}

impl Factor for OrderedLu<'_> {
    fn numeric(&mut self) {
        let stack = MemStack::new(&mut self.mem.0);
        let (val, ptr, idx) = &mut self.at;
        let at = transpose(val, ptr, idx, self.a, stack);
        let at = faer::prelude::IntoConst::into_const(at);
        factorize_supernodal_numeric_lu(
            &mut self.row_perm,
            &mut self.row_perm_inv,
            &mut self.lu,
            self.a,
            at,
            self.col_perm.as_ref(),
            &self.symbolic,
            self.par,
            stack,
            Default::default(),
        )
        .unwrap();
    }

    fn solve(&mut self, rhs: &mut [f64]) {
        let n = rhs.len();
        let x = MatMut::from_column_major_slice_mut(rhs, n, 1);
        let stack = MemStack::new(&mut self.mem.0);
        let row_perm = PermRef::new_checked(&self.row_perm, &self.row_perm_inv, n);
        self.lu.solve_in_place_with_conj(
            row_perm,
            self.col_perm.as_ref(),
            Conj::No,
            x,
            self.par,
            stack,
        );
    }

    fn nnz(&self) -> Nnz {
        Nnz::Bound(self.bound)
    }

    fn scratch(&self) -> usize {
        self.mem.1 + self.at.0.len() * 8 + (self.at.1.len() + self.at.2.len()) * size_of::<usize>()
    }

    fn kind(&self) -> &'static str {
        "supernodal"
    }
}

/// Simplicial LU on a given column ordering, for its exact `|L| + |U|`.
struct SimplicialOrderedLu<'a> {
    a: SparseColMatRef<'a, usize, f64>,
    col_perm: &'a Perm,
    lu: SimplicialLu<usize, f64>,
    row_perm: Vec<usize>,
    row_perm_inv: Vec<usize>,
    mem: (MemBuffer, usize),
}

impl<'a> SimplicialOrderedLu<'a> {
    fn new(a: SparseColMatRef<'a, usize, f64>, col_perm: &'a Perm) -> Self {
        let n = a.ncols();
        Self {
            a,
            col_perm,
            lu: SimplicialLu::new(),
            row_perm: vec![0; n],
            row_perm_inv: vec![0; n],
            mem: counted(|| {
                MemBuffer::new(factorize_simplicial_numeric_lu_scratch::<usize, f64>(n, n))
            }),
        }
    }
}

impl Factor for SimplicialOrderedLu<'_> {
    fn numeric(&mut self) {
        factorize_simplicial_numeric_lu(
            &mut self.row_perm,
            &mut self.row_perm_inv,
            &mut self.lu,
            self.a,
            self.col_perm.as_ref(),
            MemStack::new(&mut self.mem.0),
        )
        .unwrap();
    }

    fn solve(&mut self, _rhs: &mut [f64]) {
        unimplemented!("the simplicial LU is analysed, not solved with")
    }

    fn nnz(&self) -> Nnz {
        Nnz::Exact(
            self.lu.l_factor_unsorted().row_idx().len()
                + self.lu.u_factor_unsorted().row_idx().len(),
        )
    }

    fn scratch(&self) -> usize {
        self.mem.1
    }

    fn kind(&self) -> &'static str {
        "simplicial"
    }
}

/// One line of the final table.
struct Row {
    setting: String,
    nnz: String,
    mib: f64,
    fastest: f64,
    median: f64,
}

/// Sampling: measured calls per benchmark; criterion's warm-up and
/// measurement time (s).
const SAMPLES: usize = 10;

/// Run `f` as benchmark `id` (one call, one timed iteration) and record
/// its fastest and median call.
fn bench(
    c: &mut Criterion,
    id: &str,
    nnz: String,
    mib: f64,
    rows: &mut Vec<Row>,
    mut f: impl FnMut(),
) {
    let mut calls: Vec<Vec<f64>> = Vec::new();
    let mut g = c.benchmark_group("static_factor");
    g.sampling_mode(SamplingMode::Flat)
        .sample_size(SAMPLES)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(1));
    g.bench_function(id, |b| {
        b.iter_custom(|iters| {
            let mut times = Vec::with_capacity(iters as usize);
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let t = Instant::now();
                f();
                let dt = t.elapsed();
                total += dt;
                times.push(dt.as_secs_f64());
            }
            calls.push(times);
            total
        })
    });
    g.finish();
    // The last `SAMPLES` calls are the measurement (flat sampling: one
    // call per sample); those before, the warm-up.
    let mut times: Vec<f64> = calls
        .iter()
        .rev()
        .take(SAMPLES)
        .flatten()
        .copied()
        .collect();
    if times.is_empty() {
        return;
    }
    times.sort_by(f64::total_cmp);
    rows.push(Row {
        setting: id.to_string(),
        nnz,
        mib,
        fastest: times[0],
        median: times[times.len() / 2],
    });
}

/// How a factorisation is timed.
#[derive(Clone, Copy)]
enum Timing {
    /// By criterion (`SAMPLES` measured calls).
    Criterion,
    /// By this many calls, outside criterion: the settings that take
    /// seconds, where criterion's ten samples would take minutes.
    Calls(usize),
}

/// Whether benchmark `id` is asked for: no filter on the command line, or
/// one that it contains (criterion's own filter, for the settings timed
/// outside it).
fn wanted(id: &str) -> bool {
    let filters: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    filters.is_empty() || filters.iter().any(|f| id.contains(f.as_str()))
}

/// Benchmark the numeric factorisation of `make()`'s factor (and its
/// solve when `solve`), recording its size.
fn bench_factor<'a, F: Factor + 'a>(
    c: &mut Criterion,
    id: &str,
    timing: Timing,
    rows: &mut Vec<Row>,
    solve: Option<&[f64]>,
    make: impl FnOnce() -> F,
) {
    if !wanted(id) && !solve.is_some_and(|_| wanted("solve/")) {
        return;
    }
    // Bytes held by the analysis and the factor, its scratch subtracted.
    let (mut factor, held) = counted(|| {
        let mut factor = make();
        factor.numeric();
        factor
    });
    let mib = held.saturating_sub(factor.scratch()) as f64 / (1 << 20) as f64;
    let nnz = factor.nnz();
    let id = format!("{id} ({})", factor.kind());
    match timing {
        Timing::Criterion => bench(c, &id, nnz.to_string(), mib, rows, || factor.numeric()),
        Timing::Calls(calls) => {
            let mut times: Vec<f64> = (0..calls)
                .map(|_| {
                    let t = Instant::now();
                    factor.numeric();
                    t.elapsed().as_secs_f64()
                })
                .collect();
            times.sort_by(f64::total_cmp);
            eprintln!("{id}: {calls} calls, fastest {:.3} s", times[0]);
            rows.push(Row {
                setting: format!("{id}, {calls} calls"),
                nnz: nnz.to_string(),
                mib,
                fastest: times[0],
                median: times[calls / 2],
            });
        }
    }
    if let Some(b) = solve {
        let mut x = b.to_vec();
        bench(
            c,
            &format!("solve/{}", id.trim_start_matches("numeric/")),
            String::new(),
            f64::NAN,
            rows,
            || {
                x.copy_from_slice(b);
                factor.solve(&mut x);
            },
        );
    }
}

/// The spectral radius of `S⁻¹ (S − K)`, by which a Newton iteration
/// that solves with `S` (factorised in `s_factor`) in place of `K`
/// contracts the error near the solution: power iteration, 40 steps, the
/// growth over the last two taken as `ρ²` (`S` the symmetric part, `S − K`
/// is skew: with `S` positive definite the eigenvalues of `S⁻¹ (S − K)`
/// are imaginary pairs `± iμ`, which a single step does not separate).
fn contraction(
    k: SparseColMatRef<'_, usize, f64>,
    s: SparseColMatRef<'_, usize, f64>,
    s_factor: &mut impl Factor,
) -> f64 {
    let n = k.nrows();
    let norm = |v: &[f64]| v.iter().map(|t| t * t).sum::<f64>().sqrt();
    let mut v: Vec<f64> = (0..n).map(|i| ((i * 7919) % 1000) as f64 - 499.5).collect();
    let mut growth = [1.0, 1.0];
    for step in 0..40 {
        let nv = norm(&v);
        v.iter_mut().for_each(|x| *x /= nv);
        let mut w = vec![0.0; n];
        for (j, &vj) in v.iter().enumerate() {
            for p in k.col_ptr()[j]..k.col_ptr()[j + 1] {
                w[k.row_idx()[p]] += (s.val()[p] - k.val()[p]) * vj;
            }
        }
        s_factor.solve(&mut w);
        growth[step % 2] = norm(&w);
        v = w;
    }
    (growth[0] * growth[1]).sqrt()
}

/// Relative residual `‖b − K x‖ / ‖b‖` the refined solve reaches.
const REFINED: f64 = 1e-10;

/// Solve `K x = b` by iterative refinement with `m` (a factor of an
/// approximation of `K`): `x ← x + M⁻¹ (b − K x)` from `x = M⁻¹ b` until
/// `‖b − K x‖ ≤ tol ‖b‖`; returns the solves made (at most 200).
fn refine(
    k: SparseColMatRef<'_, usize, f64>,
    m: &mut impl Factor,
    b: &[f64],
    x: &mut [f64],
    tol: f64,
) -> usize {
    let norm = |v: &[f64]| v.iter().map(|t| t * t).sum::<f64>().sqrt();
    let target = tol * norm(b);
    let mut r = b.to_vec();
    x.iter_mut().for_each(|v| *v = 0.0);
    for solves in 1..=200 {
        m.solve(&mut r);
        x.iter_mut().zip(&r).for_each(|(x, d)| *x += d);
        r.copy_from_slice(b);
        for (j, &xj) in x.iter().enumerate() {
            for p in k.col_ptr()[j]..k.col_ptr()[j + 1] {
                r[k.row_idx()[p]] -= k.val()[p] * xj;
            }
        }
        if norm(&r) <= target {
            return solves;
        }
    }
    200
}

/// `‖b − A x‖ / ‖b‖`.
fn residual(a: SparseColMatRef<'_, usize, f64>, x: &[f64], b: &[f64]) -> f64 {
    let mut r = b.to_vec();
    let (col_ptr, row_idx, val) = (a.col_ptr(), a.row_idx(), a.val());
    for (j, &xj) in x.iter().enumerate() {
        for p in col_ptr[j]..col_ptr[j + 1] {
            r[row_idx[p]] -= val[p] * xj;
        }
    }
    let norm = |v: &[f64]| v.iter().map(|t| t * t).sum::<f64>().sqrt();
    norm(&r) / norm(b)
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let mut solver = release();
    let k = solver.tangent_matrix().unwrap();
    let n = k.nrows();
    let kt = transposed_index(k.symbolic());
    let (kv, kmax) = (k.val(), k.val().iter().fold(0.0f64, |m, v| m.max(v.abs())));
    let asym = (0..kv.len()).fold(0.0f64, |m, p| m.max((kv[p] - kv[kt[p]]).abs()));
    let s_val: Vec<f64> = (0..kv.len()).map(|p| 0.5 * (kv[p] + kv[kt[p]])).collect();
    let s = SparseColMat::new(k.symbolic().to_owned().unwrap(), s_val);
    eprintln!(
        "tangent: {n} equations, {} stored entries, max |K − Kᵀ| = {:.2e} max |K|",
        kv.len(),
        asym / kmax
    );
    let (k, s) = (k.as_ref(), s.as_ref());
    // The right-hand side: the internal forces of the start state, which
    // the release lets go (its first Newton step solves for a share of
    // them).
    let b: Vec<f64> = {
        let mut shells = solver
            .effect::<StaticShells<Hill48PlaneStress>>(0)
            .unwrap()
            .clone();
        let x = solver.positions();
        let (rotations, dtheta) = (
            vec![Mat3::identity(); x.len()],
            vec![Vec3::zeros(); x.len()],
        );
        let state = TrialState {
            x_start: x,
            x_committed: x,
            x,
            rotation_committed: &rotations,
            dtheta: &dtheta,
            lambda: 0.0,
        };
        let f = dense_tangent(&mut shells, &state, false).unwrap().forces;
        (0..n)
            .map(|i| {
                let (node, dof) = solver.equation_dof(i).unwrap();
                f[6 * node + dof.index()]
            })
            .collect()
    };
    let nd = nd_equations(&solver, n);
    let colamd = {
        let sym = factorize_symbolic_lu(k.symbolic(), Default::default()).unwrap();
        Perm::new(sym.col_perm().arrays().0.to_vec())
    };
    let amd = {
        let sym = cholesky_symbolic(k.symbolic(), Order::Amd, None);
        let (fwd, _) = sym.perm().expect("AMD permutes").arrays();
        Perm::new(fwd.to_vec())
    };

    // Accuracy of the factorisations that the table compares.
    {
        let mut lu = FaerLu::new(k, None, Par::Seq);
        lu.numeric();
        let mut x = b.clone();
        lu.solve(&mut x);
        let mut lu_amd = OrderedLu::new(k, &amd, Par::Seq);
        lu_amd.numeric();
        let mut y = b.clone();
        lu_amd.solve(&mut y);
        let mut llt = Cholesky::new(s, Order::Amd, None, false, Par::Seq);
        llt.numeric();
        let mut z = b.clone();
        llt.solve(&mut z);
        eprintln!(
            "relative residuals ‖b − A x‖/‖b‖: LU (COLAMD) {:.1e}, LU (AMD) {:.1e}; \
             LLᵀ of the symmetric part {:.1e} (of its own system)",
            residual(k, &x, &b),
            residual(k, &y, &b),
            residual(s, &z, &b),
        );
        eprintln!(
            "Newton with the symmetric part for the tangent: error contracted by {:.2e} per iteration",
            contraction(k, s, &mut llt)
        );
    }

    let mut rows = Vec::new();
    let rows = &mut rows;
    let seq = Par::Seq;
    let par2 = Par::rayon(2);
    // Start rayon's pool (and what faer keeps per thread) before any
    // factor's bytes are counted.
    Cholesky::new(s, Order::Amd, Some(true), false, par2).numeric();
    bench(
        &mut c,
        "symbolic/cholesky_amd",
        String::new(),
        f64::NAN,
        rows,
        || {
            let _ = cholesky_symbolic(k.symbolic(), Order::Amd, None);
        },
    );
    bench(
        &mut c,
        "symbolic/lu_colamd",
        String::new(),
        f64::NAN,
        rows,
        || {
            let _ = factorize_symbolic_lu(k.symbolic(), Default::default()).unwrap();
        },
    );

    // LU of K: the solver's settings first.
    bench_factor(
        &mut c,
        "numeric/lu_colamd",
        Timing::Criterion,
        rows,
        Some(&b),
        || FaerLu::new(k, None, seq),
    );
    bench_factor(
        &mut c,
        "numeric/lu_colamd_rayon2",
        Timing::Criterion,
        rows,
        None,
        || FaerLu::new(k, Some(true), par2),
    );
    bench_factor(
        &mut c,
        "numeric/lu_colamd",
        Timing::Calls(2),
        rows,
        None,
        || SimplicialOrderedLu::new(k, &colamd),
    );
    bench_factor(
        &mut c,
        "numeric/lu_amd",
        Timing::Criterion,
        rows,
        Some(&b),
        || OrderedLu::new(k, &amd, seq),
    );
    bench_factor(
        &mut c,
        "numeric/lu_amd",
        Timing::Calls(3),
        rows,
        None,
        || SimplicialOrderedLu::new(k, &amd),
    );
    bench_factor(
        &mut c,
        "numeric/lu_nd",
        Timing::Criterion,
        rows,
        None,
        || OrderedLu::new(k, &nd, seq),
    );

    // Cholesky of the symmetric part.
    for (name, ldlt) in [("llt", false), ("ldlt", true)] {
        bench_factor(
            &mut c,
            &format!("numeric/{name}_amd"),
            Timing::Criterion,
            rows,
            (!ldlt).then_some(&b[..]),
            || Cholesky::new(s, Order::Amd, None, ldlt, seq),
        );
        bench_factor(
            &mut c,
            &format!("numeric/{name}_amd_rayon2"),
            Timing::Criterion,
            rows,
            None,
            || Cholesky::new(s, Order::Amd, Some(true), ldlt, par2),
        );
        bench_factor(
            &mut c,
            &format!("numeric/{name}_amd"),
            Timing::Criterion,
            rows,
            None,
            || Cholesky::new(s, Order::Amd, Some(false), ldlt, seq),
        );
    }
    bench_factor(
        &mut c,
        "numeric/llt_identity",
        Timing::Criterion,
        rows,
        None,
        || Cholesky::new(s, Order::Identity, Some(true), false, seq),
    );
    bench_factor(
        &mut c,
        "numeric/llt_nd",
        Timing::Criterion,
        rows,
        None,
        || Cholesky::new(s, Order::Custom(&nd), Some(true), false, seq),
    );

    // The whole linear solve `K x = b` of a Newton iteration: LU, against
    // `LLᵀ` of the symmetric part with iterative refinement on `K`.
    if wanted("newton_solve/") {
        let mut lu = FaerLu::new(k, None, seq);
        let mut x = vec![0.0; n];
        bench(
            &mut c,
            "newton_solve/lu_colamd",
            String::new(),
            f64::NAN,
            rows,
            || {
                lu.numeric();
                x.copy_from_slice(&b);
                lu.solve(&mut x);
            },
        );
        let mut llt = Cholesky::new(s, Order::Amd, None, false, seq);
        let mut steps = 0;
        bench(
            &mut c,
            "newton_solve/llt_amd_refined",
            String::new(),
            f64::NAN,
            rows,
            || {
                llt.numeric();
                steps = refine(k, &mut llt, &b, &mut x, REFINED);
            },
        );
        eprintln!(
            "refinement on K with LLᵀ of the symmetric part: {steps} solves to ‖b − K x‖ ≤ {REFINED:e} ‖b‖"
        );
    }

    c.final_summary();
    println!("\n| setting | factor nnz | factor MiB | fastest (ms) | median (ms) |");
    println!("|---|---|---|---|---|");
    let mib = |m: f64| {
        if m.is_nan() {
            String::new()
        } else {
            format!("{m:.1}")
        }
    };
    for r in rows.iter() {
        println!(
            "| {} | {} | {} | {:.1} | {:.1} |",
            r.setting,
            r.nnz,
            mib(r.mib),
            1e3 * r.fastest,
            1e3 * r.median
        );
    }
}
