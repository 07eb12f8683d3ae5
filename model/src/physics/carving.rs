//! The material surface and the tip carving it: the tensor form of
//! `infer::Terrain` (spec §5) for a batch, each row on its own uniform grid.
//!
//! `infer` carves the tip's polyline through the time samples into a height
//! field: a node takes the lowest height of any segment that spans it. The
//! same rule is written here over all segments and nodes at once (a masked
//! minimum), so it is exact at the nodes, as `infer`'s is, and
//! differentiable almost everywhere in the tip positions: a node's height
//! follows the segment that cuts it lowest. A node moving in or out of a
//! segment's span has no gradient; the paths' ends, where that happens, lie
//! on or above the surface. Agreement with `infer`: `tests/sequence.rs`.

use burn::tensor::Tensor;

/// Height of "nothing cuts here" \[m\]: above any surface the arm reaches.
const UNCUT: f64 = 1.0e3;

/// A batch of height fields s(x): row b has nodes x_b,j = x0_b + j·dx and is
/// linear in between.
#[derive(Debug, Clone)]
pub struct Surface {
    /// Node x \[m\], `[B, G]`.
    pub x: Tensor<2>,
    /// Node heights \[m\], `[B, G]`.
    pub h: Tensor<2>,
    /// Node spacing \[m\].
    pub dx: f64,
}

impl Surface {
    /// Height at `x` (`[B, 1]`), linear between nodes as
    /// `infer::Terrain::height_at`; 0 off the grid (keep queries on it).
    pub fn height_at(&self, x: Tensor<2>) -> Tensor<2> {
        let w = ((self.x.clone() - x).abs() / self.dx).neg() + 1.0;
        (w.clamp_min(0.0) * self.h.clone()).sum_dim(1)
    }

    /// This surface after the tip's polyline `tip` (x, y, each `[B, n]`)
    /// has carved it, and the area each row lost \[m²\], `[B, 1]`
    /// (`infer::Terrain::carve_path`).
    pub fn carve(&self, tip: &[Tensor<2>; 2]) -> (Surface, Tensor<2>) {
        let n = tip[0].dims()[1];
        let ends = |v: &Tensor<2>| {
            (
                v.clone().narrow(1, 0, n - 1).unsqueeze_dim::<3>(2),
                v.clone().narrow(1, 1, n - 1).unsqueeze_dim::<3>(2),
            )
        }; // [B, S, 1] each
        let ((xa, xb), (ya, yb)) = (ends(&tip[0]), ends(&tip[1]));
        let run = xb - xa.clone();
        // A vertical segment spans at most one node exactly: moved far off
        // the grid, it spans none.
        let vertical = run.clone().abs().lower_elem(1e-12);
        let run = run.mask_fill(vertical.clone(), 1.0);
        let xa = xa.mask_fill(vertical, UNCUT);
        let nodes = self.x.clone().unsqueeze_dim::<3>(1); // [B, 1, G]
        let f = (nodes - xa) / run; // where each node lies along each segment
        let spans = f
            .clone()
            .greater_equal_elem(0.0)
            .bool_and(f.clone().lower_equal_elem(1.0));
        let height = ya.clone() + (yb - ya) * f;
        let cut = height
            .mask_fill(spans.bool_not(), UNCUT)
            .min_dim(1)
            .squeeze_dim::<2>(1); // [B, G]
        let h = self.h.clone().min_pair(cut);
        let removed = (self.h.clone() - h.clone()).sum_dim(1) * self.dx;
        (
            Surface {
                x: self.x.clone(),
                h,
                dx: self.dx,
            },
            removed,
        )
    }
}
