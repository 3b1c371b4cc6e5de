//! The skyline of a grid node: how steeply the surface rises around it, direction by direction.
//!
//! A sight line that ends at a grid node spends its last metres over the cells around that node,
//! and on a height field those are the cells whose exact test costs the most: the target's own
//! triangles always pass the bounding-box tests. A [`Skyline`] settles them once for all UAVs:
//! for each of [`SECTORS`] directions around the node, an upper bound on the slope (rise over
//! horizontal run) from the node to every point of the surface within [`REACH`] cells. A sight
//! line that arrives from direction `k` more steeply than the bound passes above all of that
//! surface, so only the stretch farther than `REACH` cells from the target is left to the UAV's
//! horizon and the walk (see [`HeightField::line_of_sight_to_node`]).
//!
//! The bounds are exact where it matters: the triangles that touch the node are planes through
//! it, bounded by their gradient over each sector; every other triangle by its plane, whose
//! height over the node divided by the triangle's nearest (or farthest) distance adds to its
//! gradient over the sector. Each bound is rounded up to one of 256 levels, so a skyline is a
//! byte per sector. The geometry shared by all nodes of a grid (which triangles, how far, which sectors)
//! is computed once, in a [`Stencil`]; [`Skylines`] keeps them per chunk of targets, computed
//! on demand. The mesh path builds the skylines of its targets the same way, from the triangles
//! of its BVH ([`SkylineBounds`]).
//!
//! Internal to [`crate::surface`], and shared by every sight line that ends at a target: the
//! grid path ([`crate::surface::heightfield`]), the mesh path ([`crate::surface::mesh`]), the
//! UAVs' horizons (`surface::horizon`) and [`crate::visibility`] with its tracker, which keep the
//! skylines per chunk of targets. It reads only [`crate::surface::grid`].
//!
//! [`HeightField::line_of_sight_to_node`]: crate::surface::heightfield::HeightField::line_of_sight_to_node

use std::sync::{Mutex, MutexGuard, PoisonError};

use crate::surface::grid::{floor_index, pseudo_angle, Grid};

/// Directions around a node; sector `k` holds the pseudo-angles `[4k, 4(k+1)) / SECTORS` (see
/// [`sector_of`]), 0.06 to 0.12 radians wide. 64 sectors reaching 6 cells made the paper's
/// missions' evaluations 12 % faster than 32 reaching 4 (benches/README.md); 128 gained nothing
/// more.
pub(crate) const SECTORS: usize = 64;

/// How far a skyline reaches, in cells: every point within `REACH * min(dx, dy)` of the node
/// horizontally is accounted for.
pub(crate) const REACH: usize = 6;

/// Slope levels: `LEVELS[q]` is the slope that code `q` stands for, strictly increasing from
/// about -64 to `+inf`: `2t / (1 - t^2)` (the tangent of twice the angle whose tangent is `t`)
/// for `t = (q + 1) / 128 - 1`: angles 0.016 rad apart near level ground, 0.008 near vertical.
/// Computed at compile time, so a look-up is a plain load.
static LEVELS: [f64; 256] = levels();

const fn levels() -> [f64; 256] {
    let mut out = [f64::INFINITY; 256];
    let mut q = 0;
    while q < 255 {
        let t = (q + 1) as f64 / 128.0 - 1.0;
        out[q] = 2.0 * t / (1.0 - t * t);
        q += 1;
    }
    out
}

/// Upper bounds on the slope from a grid node to the surface around it, per direction sector.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Skyline([u8; SECTORS]);

/// The sector of a direction given by its pseudo-angle `a` in `[0, 4]`.
#[inline(always)]
pub(crate) fn sector_of(a: f64) -> usize {
    floor_index(a * (SECTORS as f64 / 4.0), SECTORS as u32 - 1)
}

impl Skyline {
    /// Every bound `+inf`: clears nothing.
    pub(crate) const UNBOUNDED: Self = Self([255; SECTORS]);

    /// The upper bound on the slope from the node towards sector `k`, for every point of the
    /// surface within [`REACH`] cells whose direction lies within one sector of `k`; `+inf` when
    /// nothing is known, `LEVELS[0]` (about -64) where there is no surface.
    #[inline(always)]
    pub(crate) fn slope(&self, k: usize) -> f64 {
        LEVELS[self.0[k] as usize]
    }
}

/// The geometry shared by the skylines of every node of a grid: for each cell within [`REACH`]
/// of a node, where its two triangles lie from the node (distances and sectors), which depends
/// on the spacing only. Built once per grid; a skyline then only reads heights.
///
/// The triangles through the node come first, then the others in groups of one corner order
/// and one number of sectors, so that each group runs a loop of fixed length over the sectors:
/// loops whose length changed from triangle to triangle mispredicted their exit about once a
/// triangle (benches/README.md, the grid method).
#[derive(Debug, Clone)]
pub(crate) struct Stencil {
    through: Vec<(CellTriangle, Span)>,
    groups: Vec<Group>,
    edges: Box<RunEdges>,
    /// Cell size, metres.
    dx: f64,
    dy: f64,
}

/// A cell of the stencil: its offset from the node in cells (row, column) and its triangles
/// `[a, b, c]` and `[a, c, d]`.
#[derive(Debug, Clone)]
struct Cell {
    di: isize,
    dj: isize,
    tris: [Shape; 2],
}

/// Triangles clear of the node, of one corner order, each spanning `len` sectors.
#[derive(Debug, Clone)]
struct Group {
    len: usize,
    abc: bool,
    tris: Vec<AwayTriangle>,
}

/// Which triangle of which cell: the cell's offset from the node (row, column) and whether it
/// is `[a, b, c]` (else `[a, c, d]`).
#[derive(Debug, Clone, Copy)]
struct CellTriangle {
    di: isize,
    dj: isize,
    abc: bool,
}

/// A triangle clear of the node: its cell, where corner `a` lies from the node (metres), its
/// inverse nearest and farthest distances and its first sector.
#[derive(Debug, Clone, Copy)]
struct AwayTriangle {
    di: isize,
    dj: isize,
    a: (f64, f64),
    inv_near: f64,
    inv_far: f64,
    first: usize,
}

/// Where a triangle lies from the node.
#[derive(Debug, Clone, Copy)]
enum Shape {
    /// The node is one of its corners: its slope from the node is exactly `g . u`.
    Through(Span),
    /// Clear of the node, at horizontal distances in `[1 / inv_near, 1 / inv_far]`.
    Away { inv_near: f64, inv_far: f64, span: Span },
}

/// Sectors `first..=last`, or across +x when `first > last` (`first..SECTORS`, then `0..=last`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Span {
    first: usize,
    last: usize,
}

impl Span {
    /// Sectors `first..=last`, across +x when `first > last`.
    pub(crate) fn new(first: usize, last: usize) -> Self {
        debug_assert!(first < SECTORS && last < SECTORS);
        Self { first, last }
    }

    /// How many sectors.
    fn len(self) -> usize {
        if self.first <= self.last {
            self.last - self.first + 1
        } else {
            SECTORS - self.first + self.last + 1
        }
    }
}

/// Every sector.
pub(crate) const ALL_SECTORS: Span = Span { first: 0, last: SECTORS - 1 };

/// The unit vectors along the sector boundaries: `edges[k]` at pseudo-angle `4k / SECTORS`.
pub(crate) type SectorEdges = [(f64, f64); SECTORS + 1];

/// The [`SectorEdges`].
pub(crate) fn sector_edges() -> SectorEdges {
    let mut edges = [(0.0, 0.0); SECTORS + 1];
    for (k, e) in edges.iter_mut().enumerate() {
        *e = direction(4.0 * k as f64 / SECTORS as f64);
    }
    edges
}

/// A [`Skyline`] while the surface around its point is entered: a bound per sector.
pub(crate) struct SkylineBounds<'a> {
    bound: [f64; SECTORS],
    edges: &'a SectorEdges,
}

impl<'a> SkylineBounds<'a> {
    /// Nothing entered yet: no surface in any direction.
    pub(crate) fn new(edges: &'a SectorEdges) -> Self {
        Self { bound: [f64::NEG_INFINITY; SECTORS], edges }
    }

    /// Enters a plane of gradient `(gx, gy)` over the sectors of `span`: its slope from the
    /// point is at most `lift + g . u` in direction `u`.
    pub(crate) fn add_plane(&mut self, lift: f64, g: (f64, f64), span: Span) {
        add_plane(&mut self.bound, self.edges, lift, g, span.first, span.len());
    }

    /// Enters a slope of at most `slope` (NaN: unknown, `+inf`) over the sectors of `span`.
    pub(crate) fn add_slope(&mut self, slope: f64, span: Span) {
        let slope = if slope.is_nan() { f64::INFINITY } else { slope };
        for t in 0..span.len() {
            let k = (span.first + t) % SECTORS;
            self.bound[k] = self.bound[k].max(slope);
        }
    }

    /// The skyline: each sector also answers for its neighbours' directions, which absorbs the
    /// rounding of every pseudo-angle, then every bound is rounded up to a level (with a margin
    /// of 1e-9).
    pub(crate) fn finish(&self) -> Skyline {
        finish(&self.bound)
    }
}

/// [`SkylineBounds::finish`] of the bounds `bound`.
fn finish(bound: &[f64; SECTORS]) -> Skyline {
    let mut codes = [0u8; SECTORS];
    for (k, code) in codes.iter_mut().enumerate() {
        let wide = bound[(k + SECTORS - 1) % SECTORS].max(bound[k]).max(bound[(k + 1) % SECTORS]);
        *code = if wide == f64::NEG_INFINITY { 0 } else { level_above(&LEVELS, wide + 1e-9 * (1.0 + wide.abs())) };
    }
    Skyline(codes)
}

/// The gradient of the plane of triangle `[a, b, c]` (`abc`) or `[a, c, d]` of a cell with
/// corner heights `[za, zb, zc, zd]`, `inv` the inverse cell size.
#[inline(always)]
fn gradient(abc: bool, [za, zb, zc, zd]: [f64; 4], (inv_dx, inv_dy): (f64, f64)) -> (f64, f64) {
    if abc {
        ((zb - za) * inv_dx, (zc - zb) * inv_dy)
    } else {
        ((zc - zd) * inv_dx, (zd - za) * inv_dy)
    }
}

/// The lift of a plane clear of the node, of gradient `(gx, gy)`, whose corner `a` lies `rise`
/// above the node and `(ax, ay)` from it: the plane's height over the node `h0` gives it a
/// slope of `h0 / rho + g . u` from the node at distance `rho`, and `rho` is within the
/// triangle's inverse distances `(inv_near, inv_far)`.
#[inline(always)]
fn lift(rise: f64, (gx, gy): (f64, f64), (ax, ay): (f64, f64), (inv_near, inv_far): (f64, f64)) -> f64 {
    let h0 = rise - gx * ax - gy * ay;
    // Whether a plane rises above the node is as good as random from one triangle to the next:
    // a select, not a branch.
    h0 * select(h0 > 0.0, inv_near, inv_far)
}

/// Enters into `bound` a plane of gradient `(gx, gy)` over the `len` sectors from `first`: its
/// slope from the point is at most `lift + g . u` in direction `u`. Inlined where `len` is a
/// constant, it is a loop of fixed length ([`Stencil::skyline`]).
#[inline(always)]
fn add_plane(bound: &mut [f64; SECTORS], edges: &SectorEdges, lift: f64, (gx, gy): (f64, f64), first: usize, len: usize) {
    // The largest value of g . u over the unit vectors u of a sector: a sinusoid in the angle,
    // so |g| when g points into the sector, else its value at an end.
    let steepest = (gx * gx + gy * gy).sqrt();
    let (ex, ey) = edges[first];
    let (mut dot, mut right_of) = (gx * ex + gy * ey, ex * gy - ey * gx >= 0.0);
    for t in 0..len {
        let k = (first + t) % SECTORS;
        let (fx, fy) = edges[k + 1];
        let (next_dot, next_right_of) = (gx * fx + gy * fy, fx * gy - fy * gx >= 0.0);
        // `f64::max` without its NaN tests, which cost more than the rest of a sector: a NaN
        // gradient makes both dots NaN, and the top NaN either way; the bound is never NaN (a
        // NaN top leaves it as it is, as `max` would). No branches: which end is higher, and
        // whether a triangle raises a bound, are as good as random.
        let ends = if dot > next_dot { dot } else { next_dot };
        let top = lift + select(right_of && !next_right_of, steepest, ends);
        let b = &mut bound[k];
        *b = if top > *b { top } else { *b };
        (dot, right_of) = (next_dot, next_right_of);
    }
}

/// Sectors a span may reach past the wrap: a triangle within reach of a node lies within a
/// right angle seen from it (cell edges are axis-aligned, and the nearest triangles clear of the
/// node touch it), a pseudo-angle range of at most 1, so at most `SECTORS / 4 + 1` sectors.
const WRAP: usize = SECTORS / 4 + 1;

/// The x and y of the sector edges ([`SectorEdges`]), repeated past the wrap so that every
/// span is one run of them.
#[derive(Debug, Clone)]
struct RunEdges {
    x: [f64; SECTORS + WRAP + 1],
    y: [f64; SECTORS + WRAP + 1],
}

impl RunEdges {
    fn new() -> Self {
        let edges = sector_edges();
        Self { x: std::array::from_fn(|k| edges[k % SECTORS].0), y: std::array::from_fn(|k| edges[k % SECTORS].1) }
    }
}

/// [`add_plane`] into bounds kept past the wrap (`bound[SECTORS + k]` for sector `k`, folded in
/// at the end), so that a span is one run of sectors and each sector's top depends on its own
/// two edges only: no value carried from one sector to the next, and no wrap, so the loop
/// vectorises. The same operations on the same values, so the same bounds.
#[inline(always)]
fn add_plane_run(bound: &mut [f64; SECTORS + WRAP], edges: &RunEdges, lift: f64, (gx, gy): (f64, f64), first: usize, len: usize) {
    let steepest = (gx * gx + gy * gy).sqrt();
    // Each sector's two edges: from `first` and from the next one.
    let (b, e0x, e0y, e1x, e1y) = (
        &mut bound[first..first + len],
        &edges.x[first..first + len],
        &edges.y[first..first + len],
        &edges.x[first + 1..=first + len],
        &edges.y[first + 1..=first + len],
    );
    for t in 0..len {
        let (dot, next_dot) = (gx * e0x[t] + gy * e0y[t], gx * e1x[t] + gy * e1y[t]);
        let (right_of, next_right_of) = (e0x[t] * gy - e0y[t] * gx >= 0.0, e1x[t] * gy - e1y[t] * gx >= 0.0);
        let ends = if dot > next_dot { dot } else { next_dot };
        let top = lift + select(right_of && !next_right_of, steepest, ends);
        b[t] = if top > b[t] { top } else { b[t] };
    }
}

/// `if pick { a } else { b }` without a branch: in [`add_plane`]'s sweep the compiler turned
/// the two choices of a sector's top into branches, mispredicted about once a triangle.
#[inline(always)]
fn select(pick: bool, a: f64, b: f64) -> f64 {
    let mask = 0u64.wrapping_sub(u64::from(pick));
    f64::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
}

/// A grid node, as its skyline reads the grid.
struct Node<'a> {
    grid: &'a Grid,
    /// Row and column.
    i: usize,
    j: usize,
    /// The inverse cell size.
    inv: (f64, f64),
}

impl Node<'_> {
    /// Corner `a`'s height and the gradient of a triangle of the cell `(di, dj)` from the node,
    /// or `None` when the cell is off the grid. A nodata corner makes the gradient NaN (corner
    /// `a`, the height too), and with it the triangle's top in every sector: a NaN raises no
    /// bound, so the triangle counts for nothing, as in the mesh, which leaves it out.
    #[inline(always)]
    fn plane(&self, di: isize, dj: isize, abc: bool) -> Option<(f64, (f64, f64))> {
        let g = self.grid;
        let (ci, cj) = (self.i.wrapping_add_signed(di), self.j.wrapping_add_signed(dj));
        if ci >= g.ny - 1 || cj >= g.nx - 1 {
            return None; // off the grid (a negative index wraps to a huge one): no surface
        }
        let (z, nx) = (&g.z, g.nx);
        let row = ci * nx + cj;
        let (za, zb, zc, zd) = (z[row], z[row + 1], z[row + nx + 1], z[row + nx]);
        Some((za, gradient(abc, [za, zb, zc, zd], self.inv)))
    }
}

/// Enters the triangles of `group`, each over `len` sectors, into the bounds of `node`.
#[inline(always)]
fn add_group(bound: &mut [f64; SECTORS + WRAP], edges: &RunEdges, node: &Node<'_>, group: &Group, len: usize) {
    let zt = node.grid.z[node.i * node.grid.nx + node.j];
    for t in &group.tris {
        if let Some((za, g)) = node.plane(t.di, t.dj, group.abc) {
            add_plane_run(bound, edges, lift(za - zt, g, t.a, (t.inv_near, t.inv_far)), g, t.first, len);
        }
    }
}

/// [`add_group`] for groups of `L` sectors: a loop of constant length.
#[inline(always)]
fn add_fixed<const L: usize>(bound: &mut [f64; SECTORS + WRAP], edges: &RunEdges, node: &Node<'_>, group: &Group) {
    add_group(bound, edges, node, group, L);
}

/// The cells within [`REACH`] of a node, for cells of `dx` by `dy` metres: where their
/// triangles lie from the node.
fn cells(dx: f64, dy: f64) -> Vec<Cell> {
    let reach = REACH as isize;
    let mut cells = Vec::with_capacity(4 * REACH * REACH);
    for di in -reach..reach {
        for dj in -reach..reach {
            // Corners relative to the node, metres: a, b, c, d as in the mesh.
            let (x0, x1) = (dj as f64 * dx, (dj + 1) as f64 * dx);
            let (y0, y1) = (di as f64 * dy, (di + 1) as f64 * dy);
            let (a, b, c, d) = ((x0, y0), (x1, y0), (x1, y1), (x0, y1));
            let away = x0 > 0.0 || x1 < 0.0 || y0 > 0.0 || y1 < 0.0;
            let (gap_x, gap_y) = (x0.max(-x1).max(0.0), y0.max(-y1).max(0.0));
            let cell_near = (gap_x * gap_x + gap_y * gap_y).sqrt();
            let shape = |tri: [(f64, f64); 3]| {
                if !away {
                    if let Some(at) = tri.iter().position(|p| *p == (0.0, 0.0)) {
                        return Shape::Through(wedge_span(tri[(at + 1) % 3], tri[(at + 2) % 3]));
                    }
                }
                let near = if away {
                    cell_near
                } else {
                    // The triangle across the diagonal a-c from the node: no nearer than
                    // the line through a and c.
                    let (ex, ey) = (c.0 - a.0, c.1 - a.1);
                    (a.0 * ey - a.1 * ex).abs() / (ex * ex + ey * ey).sqrt()
                };
                let far = tri.iter().map(|p| (p.0 * p.0 + p.1 * p.1).sqrt()).fold(0.0, f64::max);
                Shape::Away { inv_near: 1.0 / near, inv_far: 1.0 / far, span: corner_span(&tri) }
            };
            cells.push(Cell { di, dj, tris: [shape([a, b, c]), shape([a, c, d])] });
        }
    }
    cells
}

impl Stencil {
    /// The stencil of a grid with cells of `dx` by `dy` metres.
    pub(crate) fn new(dx: f64, dy: f64) -> Self {
        let mut through = Vec::new();
        let mut groups: Vec<Group> = Vec::new();
        for cell in cells(dx, dy) {
            for (shape, abc) in cell.tris.into_iter().zip([true, false]) {
                match shape {
                    Shape::Through(span) => through.push((CellTriangle { di: cell.di, dj: cell.dj, abc }, span)),
                    Shape::Away { inv_near, inv_far, span } => {
                        let tri = AwayTriangle {
                            di: cell.di,
                            dj: cell.dj,
                            a: (cell.dj as f64 * dx, cell.di as f64 * dy),
                            inv_near,
                            inv_far,
                            first: span.first,
                        };
                        let len = span.len();
                        match groups.iter_mut().find(|g| g.len == len && g.abc == abc) {
                            Some(group) => group.tris.push(tri),
                            None => groups.push(Group { len, abc, tris: vec![tri] }),
                        }
                    }
                }
            }
        }
        groups.sort_by_key(|g| (g.len, g.abc));
        debug_assert!(groups.iter().map(|g| g.len).chain(through.iter().map(|(_, s)| s.len())).all(|len| len <= WRAP));
        Self { through, groups, edges: Box::new(RunEdges::new()), dx, dy }
    }

    /// The stencil of `grid`.
    pub(crate) fn of_grid(grid: &Grid) -> Self {
        Self::new(grid.dx, grid.dy)
    }

    /// The skyline of node `(i, j)` (row, column) of `grid` (whose spacing is the stencil's),
    /// whose height must not be nodata.
    pub(crate) fn skyline(&self, grid: &Grid, i: usize, j: usize) -> Skyline {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            #[allow(unsafe_code, reason = "a function compiled for AVX2, called where the CPU has it")]
            // SAFETY: the CPU has AVX2, the one feature `skyline_avx2` is compiled for.
            return unsafe { self.skyline_avx2(grid, i, j) };
        }
        self.skyline_anywhere(grid, i, j)
    }

    /// [`Stencil::skyline`] compiled for AVX2: the sector runs take four lanes at a time instead
    /// of two (the x86-64 baseline's), and nothing else changes: the same operations, no fused
    /// multiply-add, so the same bits.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn skyline_avx2(&self, grid: &Grid, i: usize, j: usize) -> Skyline {
        self.skyline_anywhere(grid, i, j)
    }

    /// [`Stencil::skyline`] for the target the crate is compiled for.
    #[inline(always)]
    fn skyline_anywhere(&self, grid: &Grid, i: usize, j: usize) -> Skyline {
        debug_assert!(grid.dx == self.dx && grid.dy == self.dy);
        debug_assert!(grid.z[i * grid.nx + j].is_finite());
        let node = Node { grid, i, j, inv: (1.0 / self.dx, 1.0 / self.dy) };
        let mut bound = [f64::NEG_INFINITY; SECTORS + WRAP];
        let edges = &self.edges;
        for &(t, span) in &self.through {
            if let Some((_, g)) = node.plane(t.di, t.dj, t.abc) {
                add_plane_run(&mut bound, edges, 0.0, g, span.first, span.len());
            }
        }
        for group in &self.groups {
            // A loop of constant length per group; the longest spans are 17 sectors.
            macro_rules! fixed {
                ($($n:literal)*) => {
                    match group.len {
                        $($n => add_fixed::<$n>(&mut bound, edges, &node, group),)*
                        len => add_group(&mut bound, edges, &node, group, len),
                    }
                };
            }
            fixed!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17);
        }
        let mut folded = [0.0; SECTORS];
        for (k, b) in folded.iter_mut().enumerate() {
            *b = if k < WRAP && bound[SECTORS + k] > bound[k] { bound[SECTORS + k] } else { bound[k] };
        }
        finish(&folded)
    }
}

/// The skylines of a set of targets split into chunks, computed when a sight line to a target
/// first needs one, from a chunk's second evaluation on: a chunk evaluated once (a one-off
/// coverage, the edge of a large map) is not worth the cost, while one evaluated again most
/// likely will be, many times over (an optimiser's loop). Answers never depend on it.
#[derive(Debug)]
pub(crate) struct Skylines {
    chunks: Vec<Mutex<Slot>>,
}

#[derive(Debug)]
enum Slot {
    Untouched,
    Touched,
    /// One per target of the chunk, `None` until computed.
    Kept(Box<[Option<Skyline>]>),
}

/// The skylines of one chunk, held for one evaluation of it.
pub(crate) struct ChunkSkylines<'a> {
    slot: MutexGuard<'a, Slot>,
}

impl Skylines {
    /// An empty store for targets in `n_chunks` chunks.
    pub(crate) fn new(n_chunks: usize) -> Self {
        Self { chunks: (0..n_chunks).map(|_| Mutex::new(Slot::Untouched)).collect() }
    }

    /// Number of chunks.
    pub(crate) fn n_chunks(&self) -> usize {
        self.chunks.len()
    }

    /// The skylines of chunk `c` (`len` targets), or `None` on its first evaluation.
    pub(crate) fn chunk(&self, c: usize, len: usize) -> Option<ChunkSkylines<'_>> {
        // A panic elsewhere cannot leave a slot half-written: every write is a whole value.
        let mut slot = self.chunks[c].lock().unwrap_or_else(PoisonError::into_inner);
        match *slot {
            Slot::Untouched => {
                *slot = Slot::Touched;
                return None;
            }
            Slot::Touched => *slot = Slot::Kept(vec![None; len].into_boxed_slice()),
            Slot::Kept(_) => {}
        }
        Some(ChunkSkylines { slot })
    }
}

impl ChunkSkylines<'_> {
    /// The skyline of target `t` of the chunk, from `compute` the first time it is asked for.
    pub(crate) fn get(&mut self, t: usize, compute: impl FnOnce() -> Skyline) -> Skyline {
        let Slot::Kept(kept) = &mut *self.slot else { unreachable!("a chunk is handed out only once kept") };
        *kept[t].get_or_insert_with(compute)
    }
}

/// The code of the smallest level at or above `slope` (NaN: the top level, `+inf`): from the
/// inverse of the levels' formula, then a step or two along them to correct its rounding (a
/// search by halving, eight dependent look-ups, took a tenth of a skyline's time).
fn level_above(levels: &[f64; 256], slope: f64) -> u8 {
    if slope.is_nan() || slope.abs() > 1e6 {
        return level_by_halving(levels, slope); // NaN, infinite or beyond the finite levels
    }
    // The half-angle tangent of the slope, which the level codes space evenly.
    let t = slope / (1.0 + (1.0 + slope * slope).sqrt());
    // Truncation of a value in [0, 256]: the floor, which the steps below correct.
    let mut q = (((t + 1.0) * 128.0) as usize).min(254);
    while q > 0 && levels[q - 1] >= slope {
        q -= 1;
    }
    while levels[q] < slope {
        q += 1; // levels[255] is +inf
    }
    q as u8
}

/// [`level_above`] by halving the codes.
fn level_by_halving(levels: &[f64; 256], slope: f64) -> u8 {
    if slope.is_nan() {
        return 255;
    }
    let mut lo = 0usize; // levels[q] >= slope for the answer q in [lo, lo + n)
    let mut n = 256usize;
    while n > 1 {
        let half = n / 2;
        lo += half * usize::from(levels[lo + half - 1] < slope);
        n -= half;
    }
    lo as u8
}

/// The sectors of the wedge between the directions of `p` and `q` (at most a right angle).
fn wedge_span(p: (f64, f64), q: (f64, f64)) -> Span {
    let (a, b) = (pseudo_angle(p.0, p.1), pseudo_angle(q.0, q.1));
    let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
    if hi - lo <= 2.0 {
        Span { first: sector_of(lo), last: sector_of(hi) }
    } else {
        // Wider than 2 in pseudo-angle: the wedge crosses +x.
        Span { first: sector_of(hi), last: sector_of(lo) }
    }
}

/// The sectors of the directions of a polygon clear of the node, from its corners.
pub(crate) fn corner_span(corners: &[(f64, f64)]) -> Span {
    // The polygon lies in a half-plane through the node; one below the x axis has its
    // directions along +x at pseudo-angle 4, not 0, so that its range does not wrap.
    let below = corners.iter().all(|p| p.1 <= 0.0);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in corners {
        let a = pseudo_angle(p.0, p.1);
        let a = if below && a == 0.0 { 4.0 } else { a };
        lo = lo.min(a);
        hi = hi.max(a);
    }
    Span { first: sector_of(lo), last: sector_of(hi) }
}

/// The unit vector at pseudo-angle `s` in `[0, 4]` (the inverse of [`pseudo_angle`]).
fn direction(s: f64) -> (f64, f64) {
    let (x, y) = if s < 1.0 {
        (1.0 - s, s)
    } else if s < 2.0 {
        (1.0 - s, 2.0 - s)
    } else if s < 3.0 {
        (s - 3.0, 2.0 - s)
    } else {
        (s - 3.0, s - 4.0)
    };
    let n = (x * x + y * y).sqrt();
    (x / n, y / n)
}

#[cfg(test)]
mod tests;
