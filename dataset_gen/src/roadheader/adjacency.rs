//! The adjacency rule of §3: a_ij = 1 iff the two points differ by at most
//! one increment in every joint (|θ1_i − θ1_j| ≤ Δθ1, |θ2_i − θ2_j| ≤ Δθ2,
//! |d_i − d_j| ≤ Δd; the source writes one Δθ for both angles). On the
//! joint grid these are the up to 26 cells around a point.
//!
//! Built once (improvement 1 of §4) it is a bit matrix for "are i and j
//! adjacent" and neighbour lists for "where can I go from i". The ablation
//! switches it off: then every query re-derives the answer from the joint
//! values, which is the same graph at the cost the source measured.

/// Joint grid cell of a point: (θ1, θ2, d) in increments from the ranges' minima.
pub type Cell = [i32; 3];

/// True when two cells are one step apart or less in every joint.
pub fn cells_adjacent(a: Cell, b: Cell) -> bool {
    a != b && (0..3).all(|k| (a[k] - b[k]).abs() <= 1)
}

/// The adjacency of a point set, built once or re-derived per query.
#[derive(Debug, Clone)]
pub struct Adjacency {
    cells: Vec<Cell>,
    /// Row-major n × n bits, `words` u64 per row; empty when not built.
    bits: Vec<u64>,
    words: usize,
    /// Neighbour lists: `targets[offsets[i]..offsets[i + 1]]`.
    offsets: Vec<usize>,
    targets: Vec<u32>,
    built: bool,
}

impl Adjacency {
    /// The adjacency of `cells`; `built` = false keeps no matrix or lists.
    pub fn new(cells: Vec<Cell>, built: bool) -> Self {
        let n = cells.len();
        let words = n.div_ceil(64);
        let mut adj = Adjacency {
            cells,
            bits: Vec::new(),
            words,
            offsets: vec![0],
            targets: Vec::new(),
            built: false,
        };
        if built {
            let mut bits = vec![0u64; n * words];
            let mut offsets = Vec::with_capacity(n + 1);
            let mut targets = Vec::new();
            offsets.push(0);
            for i in 0..n {
                adj.scan(i, |j| {
                    bits[i * words + j as usize / 64] |= 1 << (j % 64);
                    targets.push(j);
                });
                offsets.push(targets.len());
            }
            adj.bits = bits;
            adj.offsets = offsets;
            adj.targets = targets;
            adj.built = true;
        }
        adj
    }

    /// Re-derives the neighbours of `i` from the cells of all points.
    fn scan(&self, i: usize, mut f: impl FnMut(u32)) {
        let c = self.cells[i];
        for (j, &d) in self.cells.iter().enumerate() {
            if cells_adjacent(c, d) {
                f(j as u32);
            }
        }
    }

    pub fn len(&self) -> usize {
        self.cells.len()
    }

    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    pub fn cell(&self, i: u32) -> Cell {
        self.cells[i as usize]
    }

    /// Whether the matrix and lists were built.
    pub fn is_built(&self) -> bool {
        self.built
    }

    #[inline]
    pub fn adjacent(&self, i: u32, j: u32) -> bool {
        if self.built {
            self.bits[i as usize * self.words + j as usize / 64] >> (j % 64) & 1 == 1
        } else {
            cells_adjacent(self.cells[i as usize], self.cells[j as usize])
        }
    }

    /// Calls `f` for every neighbour of `i`, in index order.
    #[inline]
    pub fn for_each_neighbour(&self, i: u32, mut f: impl FnMut(u32)) {
        if self.built {
            let i = i as usize;
            for &j in &self.targets[self.offsets[i]..self.offsets[i + 1]] {
                f(j);
            }
        } else {
            self.scan(i as usize, f);
        }
    }

    /// Sizes of the connected pieces, largest first.
    pub fn component_sizes(&self) -> Vec<usize> {
        let n = self.len();
        let mut seen = vec![false; n];
        let mut sizes = Vec::new();
        let mut stack = Vec::new();
        for s in 0..n {
            if seen[s] {
                continue;
            }
            seen[s] = true;
            stack.push(s as u32);
            let mut size = 0;
            while let Some(v) = stack.pop() {
                size += 1;
                self.for_each_neighbour(v, |w| {
                    if !seen[w as usize] {
                        seen[w as usize] = true;
                        stack.push(w);
                    }
                });
            }
            sizes.push(size);
        }
        sizes.sort_unstable_by(|a, b| b.cmp(a));
        sizes
    }
}
