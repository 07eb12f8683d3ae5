//! Which stored tasks are nearest a new one.

use crate::trench::TrenchTask;

/// Most stored tasks one search takes as neighbours.
pub const MAX_NEIGHBOURS: usize = 8;

/// L, D, β1, β2 and far edge: the space in which tasks are near or far.
pub fn features(t: &TrenchTask) -> [f64; 5] {
    [t.length, t.depth, t.slope_far, t.slope_near, t.far_edge]
}

/// Indices of the `k` (at most [`MAX_NEIGHBOURS`]) stored tasks nearest
/// `task`, nearest first (ties: the earlier), each stored task given with
/// its plan's dig count. Task features are scaled by their spread over the
/// stored tasks. The nearest stored task with `digs` digs (the task's
/// expected count) is always among them (last, if it was not already): a
/// neighbour with fewer digs leaves material.
pub fn nearest<I>(
    stored: I,
    task: &TrenchTask,
    digs: usize,
    k: usize,
) -> [Option<usize>; MAX_NEIGHBOURS]
where
    I: Iterator<Item = (TrenchTask, usize)> + Clone,
{
    let mut lo = [f64::INFINITY; 5];
    let mut hi = [f64::NEG_INFINITY; 5];
    for (t, _) in stored.clone() {
        for (i, f) in features(&t).into_iter().enumerate() {
            lo[i] = lo[i].min(f);
            hi[i] = hi[i].max(f);
        }
    }
    let span: [f64; 5] = core::array::from_fn(|i| (hi[i] - lo[i]).max(1e-6));
    let at = features(task);
    let distance = |t: &TrenchTask| {
        let f = features(t);
        (0..5)
            .map(|i| {
                let d = (f[i] - at[i]) / span[i];
                d * d
            })
            .sum::<f64>()
    };
    let k = k.min(MAX_NEIGHBOURS);
    let mut near: [Option<(f64, usize)>; MAX_NEIGHBOURS] = [None; MAX_NEIGHBOURS];
    if k == 0 {
        return near.map(|_| None);
    }
    let mut matched: Option<(f64, usize)> = None;
    for (i, (t, count)) in stored.enumerate() {
        let d = distance(&t);
        if count == digs && matched.is_none_or(|(e, _)| d < e) {
            matched = Some((d, i));
        }
        // Kept sorted; an equal distance goes after the earlier task.
        let Some(pos) = near[..k].iter().position(|s| s.is_none_or(|(e, _)| d < e)) else {
            continue;
        };
        near[pos..k].rotate_right(1);
        near[pos] = Some((d, i));
    }
    // The nearest stored task with the task's dig count is always tried (last).
    if let Some(m) = matched.filter(|(_, i)| !near[..k].iter().flatten().any(|(_, j)| j == i)) {
        near[k - 1] = Some(m);
    }
    near.map(|s| s.map(|(_, i)| i))
}
