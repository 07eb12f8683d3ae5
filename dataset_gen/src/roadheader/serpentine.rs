//! The serpentine (boustrophedon) sweep an operator cuts by hand: plane
//! by plane from the outermost (least d), row by row in θ1 (alternating
//! up and down between planes), each row in θ2, alternating direction.
//! Where rows differ in extent the jump between rows may break the
//! adjacency rule; [`super::Objectives`] counts such jumps as violations.

use super::instance::Instance;
use std::collections::BTreeMap;

/// The serpentine order of `inst`'s points.
pub fn serpentine(inst: &Instance) -> Vec<u32> {
    let mut planes: BTreeMap<i32, BTreeMap<i32, Vec<u32>>> = BTreeMap::new();
    for (i, p) in inst.points.iter().enumerate() {
        planes
            .entry(p.cell[2])
            .or_default()
            .entry(p.cell[0])
            .or_default()
            .push(i as u32);
    }
    let mut order = Vec::with_capacity(inst.len());
    let mut row_count = 0;
    for (plane_index, rows) in planes.into_values().enumerate() {
        let rows: Vec<Vec<u32>> = if plane_index % 2 == 0 {
            rows.into_values().collect()
        } else {
            rows.into_values().rev().collect()
        };
        for mut row in rows {
            row.sort_by_key(|&i| inst.points[i as usize].cell[1]);
            if row_count % 2 == 1 {
                row.reverse();
            }
            order.extend(row);
            row_count += 1;
        }
    }
    order
}
