//! Neighbour queries on a cloud through kiddo's immutable k-d tree (f32
//! coordinates, u32 item = the point's index). Kiddo was chosen over a tree
//! of our own: pure Rust, no unsafe in our code, allocation-free radius
//! visits with caller-owned scratch, and among the fastest k-d trees for
//! 3-D queries.

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use std::num::NonZero;

/// A cloud and its k-d tree.
#[derive(Debug)]
pub struct Neighbours<'a> {
    pub points: &'a [[f32; 3]],
    tree: ImmutableKdTree<f32, 3>,
}

impl<'a> Neighbours<'a> {
    /// Builds the tree (the cloud must hold fewer than 2³² points).
    pub fn new(points: &'a [[f32; 3]]) -> Self {
        let tree = ImmutableKdTree::new_from_slice(points)
            .expect("a k-d tree over finite points of at most u32::MAX items");
        Self { points, tree }
    }

    /// Calls `visit(index, squared distance)` for every point q with
    /// |q − p| ≤ `radius` (inclusive), p itself included if it is in the cloud.
    pub fn within(&self, p: &[f32; 3], radius: f32, mut visit: impl FnMut(usize, f32)) {
        self.tree
            .query(p)
            .within::<SquaredEuclidean<f32>>(radius * radius)
            .unsorted()
            .visit(|r| visit(r.item as usize, r.distance));
    }

    /// The `k` nearest points to point `i` other than `i` itself, as
    /// (squared distance, index), nearest first.
    pub fn nearest_others(&self, i: usize, k: usize) -> Vec<(f32, usize)> {
        let n = NonZero::new(k + 1).expect("k + 1 > 0");
        let mut out: Vec<(f32, usize)> = self
            .tree
            .query(&self.points[i])
            .nearest_n::<SquaredEuclidean<f32>>(n)
            .execute()
            .into_iter()
            .filter(|r| r.item as usize != i)
            .map(|r| (r.distance, r.item as usize))
            .collect();
        out.truncate(k);
        out
    }
}
