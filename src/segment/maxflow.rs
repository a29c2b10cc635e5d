//! Boykov–Kolmogorov max-flow ("An experimental comparison of min-cut/max-flow algorithms for
//! energy minimization in vision", PAMI 2004) specialised for 4-connected image grids.
//!
//! Written here rather than taken from a crate: the general-purpose Rust max-flow crates
//! (`pathfinding`'s Edmonds–Karp, petgraph's Ford–Fulkerson) are augmenting-path solvers that
//! rebuild search trees from scratch and take seconds on a 640×480 grid, and a general graph
//! with pointer-linked arcs pays for its generality. On a grid the arcs of a node are implicit (its
//! four neighbours), so every per-node quantity is a flat array indexed by pixel, residual
//! capacities sit at `4·p + direction`, the reverse arc of direction `k` is `k ^ 2`, and a
//! parent is a 2-bit direction. Capacities are integers, so the flow is exact and the result does
//! not depend on rounding.
//!
//! The two search trees (S from the source, T to the sink) are grown, augmented along and repaired
//! (orphan adoption with the timestamp/distance heuristic) exactly as in the paper; the storage is
//! allocated once for the largest grid and reused from frame to frame.

use std::collections::VecDeque;

/// Direction offsets: 0 right, 1 down, 2 left, 3 up; the reverse of `k` is `k ^ 2`.
const DIRS: usize = 4;
/// Parent marker: the node hangs directly off its terminal.
const TERMINAL: u8 = 4;
/// Parent marker: the node lost its parent and waits for adoption.
const ORPHAN: u8 = 5;
/// Parent marker: the node is in no tree.
const NONE: u8 = 6;

const FREE: u8 = 0;
const SRC: u8 = 1;
const SNK: u8 = 2;

/// A 4-connected grid graph with source and sink links, and the BK solver's state.
#[derive(Clone, Debug, Default)]
pub struct GridFlow {
    w: usize,
    h: usize,
    /// Residual terminal capacity: positive from the source, negative to the sink.
    tr: Vec<i32>,
    /// Residual capacity of the arc from `p` towards direction `k`, at `4·p + k`.
    cap: Vec<i32>,
    parent: Vec<u8>,
    tree: Vec<u8>,
    ts: Vec<u32>,
    dist: Vec<u32>,
    queued: Vec<bool>,
    /// Bit `k` set when the neighbour in direction `k` exists.
    inside: Vec<u8>,
    active: VecDeque<u32>,
    orphans: VecDeque<u32>,
    time: u32,
    /// Flow already routed by [`GridFlow::set_terminals`] (`min(source, sink)` per node).
    flow: i64,
}

impl GridFlow {
    /// An empty solver; [`GridFlow::reset`] sizes it.
    pub fn new() -> Self {
        Self::default()
    }

    /// Starts a new `w × h` graph with every capacity zero. Storage only grows, so calling this
    /// every frame with the same size allocates nothing.
    pub fn reset(&mut self, w: usize, h: usize) {
        let n = w * h;
        let same_shape = self.inside.len() == n && self.w == w;
        self.w = w;
        self.h = h;
        resize_fill(&mut self.tr, n, 0);
        resize_fill(&mut self.cap, n * DIRS, 0);
        resize_fill(&mut self.parent, n, NONE);
        resize_fill(&mut self.tree, n, FREE);
        resize_fill(&mut self.ts, n, 0);
        resize_fill(&mut self.dist, n, 0);
        resize_fill(&mut self.queued, n, false);
        if !same_shape {
            self.inside.clear();
            self.inside.extend((0..n).map(|p| {
                let (u, v) = (p % w, p / w);
                u8::from(u + 1 < w)
                    | u8::from(v + 1 < h) << 1
                    | u8::from(u > 0) << 2
                    | u8::from(v > 0) << 3
            }));
        }
        self.active.clear();
        self.orphans.clear();
        self.time = 0;
        self.flow = 0;
    }

    /// Grid width.
    pub fn width(&self) -> usize {
        self.w
    }

    /// Grid height.
    pub fn height(&self) -> usize {
        self.h
    }

    /// Sets node `p`'s link capacities: `source` is paid if `p` ends on the sink side, `sink` if
    /// it ends on the source side. Only the difference needs a residual arc.
    #[inline]
    pub fn set_terminals(&mut self, p: usize, source: i32, sink: i32) {
        self.flow += i64::from(source.min(sink));
        self.tr[p] = source - sink;
    }

    /// Sets the capacities of the edge between `p` and its right neighbour (`k = 0`) or the one
    /// below it (`k = 1`): `fwd` from `p` to the neighbour, `rev` back.
    #[inline]
    pub fn set_edge(&mut self, p: usize, k: usize, fwd: i32, rev: i32) {
        debug_assert!(k < 2);
        let q = if k == 0 { p + 1 } else { p + self.w };
        self.cap[DIRS * p + k] = fwd;
        self.cap[DIRS * q + (k ^ 2)] = rev;
    }

    /// True when node `p` ended on the source side of the minimum cut.
    #[inline]
    pub fn is_source(&self, p: usize) -> bool {
        self.tree[p] == SRC
    }

    /// The neighbour of `p` in direction `k`, if inside the grid (a bit test, no division).
    #[inline(always)]
    fn neighbour(&self, p: usize, k: u8) -> Option<usize> {
        if self.inside[p] >> k & 1 == 0 {
            return None;
        }
        Some(match k {
            0 => p + 1,
            1 => p + self.w,
            2 => p - 1,
            _ => p - self.w,
        })
    }

    #[inline(always)]
    fn set_active(&mut self, p: usize) {
        if !self.queued[p] {
            self.queued[p] = true;
            self.active.push_back(p as u32);
        }
    }

    fn next_active(&mut self) -> Option<usize> {
        while let Some(p) = self.active.pop_front() {
            let p = p as usize;
            self.queued[p] = false;
            if self.parent[p] != NONE {
                return Some(p);
            }
        }
        None
    }

    /// Computes the maximum flow (= the minimum cut's cost) and leaves the cut readable through
    /// [`GridFlow::is_source`]. Nodes in neither tree end on the sink side.
    pub fn maxflow(&mut self) -> i64 {
        let n = self.w * self.h;
        for p in 0..n {
            let t = self.tr[p];
            if t != 0 {
                self.tree[p] = if t > 0 { SRC } else { SNK };
                self.parent[p] = TERMINAL;
                self.ts[p] = 0;
                self.dist[p] = 1;
                self.set_active(p);
            }
        }
        let mut current: Option<usize> = None;
        loop {
            let p = match current.filter(|&p| self.parent[p] != NONE) {
                Some(p) => p,
                None => match self.next_active() {
                    Some(p) => p,
                    None => break,
                },
            };
            // Growth: find an arc joining the two trees, growing p's tree into free nodes.
            let mut meet = None;
            let tree = self.tree[p];
            for k in 0..DIRS as u8 {
                let Some(q) = self.neighbour(p, k) else {
                    continue;
                };
                // Residual capacity in the direction the tree grows: out of S, into T.
                let c = if tree == SRC {
                    self.cap[DIRS * p + k as usize]
                } else {
                    self.cap[DIRS * q + (k as usize ^ 2)]
                };
                if c <= 0 {
                    continue;
                }
                if self.parent[q] == NONE {
                    self.tree[q] = tree;
                    self.parent[q] = k ^ 2;
                    self.ts[q] = self.ts[p];
                    self.dist[q] = self.dist[p] + 1;
                    self.set_active(q);
                } else if self.tree[q] != tree {
                    meet = Some((p, k));
                    break;
                } else if self.ts[q] <= self.ts[p] && self.dist[q] > self.dist[p] {
                    // Shorter path to the terminal through p: re-hang q (BK's heuristic).
                    self.parent[q] = k ^ 2;
                    self.ts[q] = self.ts[p];
                    self.dist[q] = self.dist[p] + 1;
                }
            }
            self.time += 1;
            match meet {
                Some((p, k)) => {
                    current = Some(p);
                    self.augment(p, k);
                    self.adopt();
                }
                None => current = None,
            }
        }
        self.flow
    }

    /// Pushes the bottleneck along source → … → (p —k→ q or q → p) → … → sink.
    fn augment(&mut self, p: usize, k: u8) {
        let q = self
            .neighbour(p, k)
            .expect("meeting arc is inside the grid");
        // Orient the meeting arc from the S node to the T node.
        let (s_node, t_node, mid) = if self.tree[p] == SRC {
            (p, q, DIRS * p + k as usize)
        } else {
            (q, p, DIRS * q + (k as usize ^ 2))
        };
        let mut b = self.cap[mid];
        // Bottleneck on the source side: arcs parent → child.
        let mut x = s_node;
        loop {
            let pk = self.parent[x];
            if pk == TERMINAL {
                b = b.min(self.tr[x]);
                break;
            }
            let y = self.neighbour(x, pk).expect("parent inside grid");
            b = b.min(self.cap[DIRS * y + (pk as usize ^ 2)]);
            x = y;
        }
        // Sink side: arcs child → parent.
        let mut x = t_node;
        loop {
            let pk = self.parent[x];
            if pk == TERMINAL {
                b = b.min(-self.tr[x]);
                break;
            }
            b = b.min(self.cap[DIRS * x + pk as usize]);
            x = self.neighbour(x, pk).expect("parent inside grid");
        }
        // Push b.
        let mid_rev = if s_node == p {
            DIRS * q + (k as usize ^ 2)
        } else {
            DIRS * p + k as usize
        };
        self.cap[mid] -= b;
        self.cap[mid_rev] += b;
        let mut x = s_node;
        loop {
            let pk = self.parent[x];
            if pk == TERMINAL {
                self.tr[x] -= b;
                if self.tr[x] == 0 {
                    self.make_orphan_front(x);
                }
                break;
            }
            let y = self.neighbour(x, pk).expect("parent inside grid");
            self.cap[DIRS * y + (pk as usize ^ 2)] -= b;
            self.cap[DIRS * x + pk as usize] += b;
            if self.cap[DIRS * y + (pk as usize ^ 2)] == 0 {
                self.make_orphan_front(x);
            }
            x = y;
        }
        let mut x = t_node;
        loop {
            let pk = self.parent[x];
            if pk == TERMINAL {
                self.tr[x] += b;
                if self.tr[x] == 0 {
                    self.make_orphan_front(x);
                }
                break;
            }
            let y = self.neighbour(x, pk).expect("parent inside grid");
            self.cap[DIRS * x + pk as usize] -= b;
            self.cap[DIRS * y + (pk as usize ^ 2)] += b;
            if self.cap[DIRS * x + pk as usize] == 0 {
                self.make_orphan_front(x);
            }
            x = y;
        }
        self.flow += i64::from(b);
    }

    #[inline]
    fn make_orphan_front(&mut self, x: usize) {
        self.parent[x] = ORPHAN;
        self.orphans.push_front(x as u32);
    }

    /// Repairs both trees after an augmentation: each orphan finds a new parent in its tree whose
    /// path reaches the terminal, or leaves the tree and orphans its children.
    fn adopt(&mut self) {
        while let Some(x) = self.orphans.pop_front() {
            let x = x as usize;
            let tree = self.tree[x];
            let mut best: Option<(u8, u32)> = None;
            for k in 0..DIRS as u8 {
                let Some(q) = self.neighbour(x, k) else {
                    continue;
                };
                if self.tree[q] != tree || self.parent[q] == NONE {
                    continue;
                }
                // Residual arc from the candidate parent towards the root's flow direction.
                let c = if tree == SRC {
                    self.cap[DIRS * q + (k as usize ^ 2)]
                } else {
                    self.cap[DIRS * x + k as usize]
                };
                if c <= 0 {
                    continue;
                }
                if let Some(d) = self.origin_distance(q) {
                    if best.is_none_or(|(_, bd)| d < bd) {
                        best = Some((k, d));
                    }
                    // Stamp the path just checked so later walks stop early.
                    let mut j = q;
                    let mut dd = d;
                    while self.ts[j] != self.time {
                        self.ts[j] = self.time;
                        self.dist[j] = dd;
                        dd -= 1;
                        let pk = self.parent[j];
                        if pk == TERMINAL {
                            break;
                        }
                        j = self.neighbour(j, pk).expect("parent inside grid");
                    }
                }
            }
            if let Some((k, d)) = best {
                self.parent[x] = k;
                self.ts[x] = self.time;
                self.dist[x] = d + 1;
                continue;
            }
            // No parent: x leaves its tree; neighbours that could feed it become active, its
            // children become orphans.
            for k in 0..DIRS as u8 {
                let Some(q) = self.neighbour(x, k) else {
                    continue;
                };
                if self.tree[q] != tree || self.parent[q] == NONE {
                    continue;
                }
                let c = if tree == SRC {
                    self.cap[DIRS * q + (k as usize ^ 2)]
                } else {
                    self.cap[DIRS * x + k as usize]
                };
                if c > 0 {
                    self.set_active(q);
                }
                let pq = self.parent[q];
                if pq < TERMINAL && pq == (k ^ 2) {
                    self.parent[q] = ORPHAN;
                    self.orphans.push_back(q as u32);
                }
            }
            self.parent[x] = NONE;
            self.tree[x] = FREE;
        }
    }

    /// Distance from `q` to its terminal along parent links, or `None` if the path ends in an
    /// orphan. Stops early at a node stamped in this round.
    fn origin_distance(&self, mut j: usize) -> Option<u32> {
        let mut d = 0u32;
        loop {
            if self.ts[j] == self.time {
                return Some(d + self.dist[j]);
            }
            let pk = self.parent[j];
            d += 1;
            if pk == TERMINAL {
                // The terminal's own child: distance 1 (stamped by the caller).
                return Some(d);
            }
            if pk == ORPHAN || pk == NONE {
                return None;
            }
            j = self.neighbour(j, pk).expect("parent inside grid");
        }
    }
}

fn resize_fill<T: Copy>(v: &mut Vec<T>, n: usize, x: T) {
    v.clear();
    v.resize(n, x);
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A random small grid: terminal capacities and edge capacities (0 sometimes, to make
    /// disconnected regions and ties).
    struct Problem {
        w: usize,
        h: usize,
        src: Vec<i32>,
        snk: Vec<i32>,
        /// (p, k, fwd, rev) for k in {0 right, 1 down}.
        edges: Vec<(usize, usize, i32, i32)>,
    }

    fn random_problem(rng: &mut ChaCha8Rng) -> Problem {
        let w = rng.random_range(1..=4);
        let h = rng.random_range(1..=4);
        let n = w * h;
        let cap = |rng: &mut ChaCha8Rng| {
            if rng.random_bool(0.25) {
                0
            } else {
                rng.random_range(0..20)
            }
        };
        let src = (0..n).map(|_| cap(rng)).collect();
        let snk = (0..n).map(|_| cap(rng)).collect();
        let mut edges = Vec::new();
        for p in 0..n {
            if p % w + 1 < w {
                edges.push((p, 0, cap(rng), cap(rng)));
            }
            if p / w + 1 < h {
                edges.push((p, 1, cap(rng), cap(rng)));
            }
        }
        Problem {
            w,
            h,
            src,
            snk,
            edges,
        }
    }

    /// Cost of a cut: `side[p]` true = source side.
    fn cut_cost(pr: &Problem, side: &[bool]) -> i64 {
        let mut c = 0i64;
        for ((&s, &src), &snk) in side.iter().zip(&pr.src).zip(&pr.snk) {
            c += i64::from(if s { snk } else { src });
        }
        for &(p, k, fwd, rev) in &pr.edges {
            let q = if k == 0 { p + 1 } else { p + pr.w };
            if side[p] && !side[q] {
                c += i64::from(fwd);
            }
            if !side[p] && side[q] {
                c += i64::from(rev);
            }
        }
        c
    }

    /// The reference: the cheapest of all 2^n cuts.
    fn brute_force_min_cut(pr: &Problem) -> i64 {
        let n = pr.w * pr.h;
        (0..1u32 << n)
            .map(|m| cut_cost(pr, &(0..n).map(|p| m >> p & 1 == 1).collect::<Vec<_>>()))
            .min()
            .unwrap()
    }

    #[test]
    fn matches_brute_force_min_cut_on_random_small_grids() {
        let mut rng = ChaCha8Rng::seed_from_u64(42);
        let mut g = GridFlow::new();
        for _ in 0..2000 {
            let pr = random_problem(&mut rng);
            g.reset(pr.w, pr.h);
            for p in 0..pr.w * pr.h {
                g.set_terminals(p, pr.src[p], pr.snk[p]);
            }
            for &(p, k, f, r) in &pr.edges {
                g.set_edge(p, k, f, r);
            }
            let flow = g.maxflow();
            let want = brute_force_min_cut(&pr);
            assert_eq!(flow, want, "{}x{}", pr.w, pr.h);
            // The cut the solver reports costs exactly the flow (max-flow = min-cut).
            let side: Vec<bool> = (0..pr.w * pr.h).map(|p| g.is_source(p)).collect();
            assert_eq!(cut_cost(&pr, &side), want);
        }
    }

    #[test]
    fn separates_two_halves_along_the_cheapest_column() {
        // 8×3 grid: left column tied to the source, right column to the sink, horizontal edges
        // cost 10 except between columns 4 and 5 (cost 1): the cut runs there, flow 3·1.
        let mut g = GridFlow::new();
        g.reset(8, 3);
        for v in 0..3 {
            g.set_terminals(v * 8, 1000, 0);
            g.set_terminals(v * 8 + 7, 0, 1000);
            for u in 0..7 {
                let c = if u == 4 { 1 } else { 10 };
                g.set_edge(v * 8 + u, 0, c, c);
            }
        }
        assert_eq!(g.maxflow(), 3);
        for v in 0..3 {
            for u in 0..8 {
                assert_eq!(g.is_source(v * 8 + u), u <= 4, "({u}, {v})");
            }
        }
    }
}
