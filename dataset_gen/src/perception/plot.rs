//! The picture a person checks: the cloud before and after filtering, from
//! the side (x–z) and from above (x–y), with the fitted surface's section
//! at the middle of the pile (and the true one for a generated pile), and
//! the fitted points coloured by their residual z − f(x, y).

use super::chain::Perception;
use super::error::PerceptionError;
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::Path;

/// Most points drawn per cloud (every k-th point), to keep the SVG small.
const MAX_DRAWN: usize = 2_500;

/// About MAX_DRAWN points, picked by a hash of the index (every k-th point
/// would draw the scan's grid rows as stripes).
fn thin(points: &[[f32; 3]]) -> impl Iterator<Item = &[f32; 3]> {
    let k = points.len().div_ceil(MAX_DRAWN).max(1) as u64;
    points
        .iter()
        .enumerate()
        .filter(move |(i, _)| crate::rng::splitmix64(*i as u64).is_multiple_of(k))
        .map(|(_, p)| p)
}

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

fn err(e: impl std::fmt::Display) -> PerceptionError {
    PerceptionError::Output {
        what: "SVG",
        detail: e.to_string(),
    }
}

type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A titled chart over `ranges` with its mesh drawn: x from the toe, `y_desc` up.
fn chart<'a, 'b>(
    area: &'a Area<'b>,
    title: &str,
    ranges: (std::ops::Range<f64>, std::ops::Range<f64>),
    y_desc: &str,
) -> Result<Chart<'a, 'b>, PerceptionError> {
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(50)
        .build_cartesian_2d(ranges.0, ranges.1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("x from the toe (m)")
        .y_desc(y_desc)
        .draw()
        .map_err(err)?;
    Ok(chart)
}

/// Axis ranges: the levelled cloud's extent, clipped to a sane window.
fn extent(points: &[[f32; 3]], axis: usize, lo: f32, hi: f32) -> std::ops::Range<f64> {
    let (mut a, mut b) = (f32::INFINITY, f32::NEG_INFINITY);
    for p in points {
        a = a.min(p[axis]);
        b = b.max(p[axis]);
    }
    (a.max(lo) as f64 - 0.02)..(b.min(hi) as f64 + 0.02)
}

/// Side view: `points` as (x, z), the fitted section at the middle y, the true one if given.
fn side(
    area: &Area,
    title: &str,
    points: &[[f32; 3]],
    colour: RGBColor,
    p: &Perception,
    truth: Option<&dyn Fn(f64, f64) -> f64>,
    ranges: (std::ops::Range<f64>, std::ops::Range<f64>),
) -> Result<(), PerceptionError> {
    let mut chart = chart(area, title, ranges, "z (m)")?;
    chart
        .draw_series(
            thin(points).map(|q| Circle::new((q[0] as f64, q[2] as f64), 1, colour.filled())),
        )
        .map_err(err)?;
    let d = p.surface.domain;
    let yc = 0.5 * (d.y[0] + d.y[1]);
    let xs = (0..=200).map(|i| d.x[0] + (d.x[1] - d.x[0]) * i as f64 / 200.0);
    if let Some(h) = truth {
        let green = RGBColor(30, 150, 30);
        chart
            .draw_series(LineSeries::new(
                xs.clone().map(|x| (x, h(x, yc))),
                green.stroke_width(5),
            ))
            .map_err(err)?
            .label(format!("true surface, y = {yc:.3} m"))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], green.stroke_width(5)));
    }
    chart
        .draw_series(LineSeries::new(
            xs.filter_map(|x| p.surface.height(x, yc).ok().map(|z| (x, z))),
            RED.stroke_width(1),
        ))
        .map_err(err)?
        .label(format!(
            "fitted surface, y = {yc:.3} m (R² = {:.4})",
            p.surface.r_squared
        ))
        .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], RED.stroke_width(1)));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(err)
}

/// Top view: `points` as (x, y), each coloured by `colour(point)`.
fn top(
    area: &Area,
    title: &str,
    points: &[[f32; 3]],
    colour: impl Fn(&[f32; 3]) -> RGBColor,
    ranges: (std::ops::Range<f64>, std::ops::Range<f64>),
) -> Result<(), PerceptionError> {
    let mut chart = chart(area, title, ranges, "y across (m)")?;
    chart
        .draw_series(
            thin(points).map(|q| Circle::new((q[0] as f64, q[1] as f64), 1, colour(q).filled())),
        )
        .map_err(err)?;
    Ok(())
}

/// Writes the 2 × 2 picture to `path`.
pub fn write_svg(
    path: &Path,
    title: &str,
    p: &Perception,
    truth: Option<&dyn Fn(f64, f64) -> f64>,
) -> Result<(), PerceptionError> {
    let root = SVGBackend::new(path, (1300, 950)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let root = root.titled(title, ("sans-serif", 20)).map_err(err)?;
    let panels = root.split_evenly((2, 2));
    let xr = extent(&p.levelled, 0, -1.0, 1.5);
    let zr = extent(&p.levelled, 2, -0.05, 1.0);
    let yr = extent(&p.levelled, 1, -1.0, 1.0);
    let grey = RGBColor(150, 150, 150);
    let blue = RGBColor(40, 90, 200);
    side(
        &panels[0],
        &format!("side, levelled scan ({} points)", p.levelled.len()),
        &p.levelled,
        grey,
        p,
        truth,
        (xr.clone(), zr.clone()),
    )?;
    side(
        &panels[1],
        &format!("side, filtered and smoothed ({} points)", p.smoothed.len()),
        &p.smoothed,
        blue,
        p,
        truth,
        (xr.clone(), zr),
    )?;
    let height = |q: &[f32; 3]| {
        let t = (q[2].clamp(0.0, 0.6) / 0.6) as f64;
        RGBColor((40.0 + 200.0 * t) as u8, 90, (220.0 - 180.0 * t) as u8)
    };
    top(
        &panels[2],
        "top, levelled scan (colour: height 0–0.6 m)",
        &p.levelled,
        height,
        (xr.clone(), yr.clone()),
    )?;
    let residual = |q: &[f32; 3]| {
        let r = p
            .surface
            .height(q[0] as f64, q[1] as f64)
            .map(|z| q[2] as f64 - z)
            .unwrap_or(0.0);
        let t = (r / 0.005).clamp(-1.0, 1.0);
        if t >= 0.0 {
            RGBColor(255, (255.0 * (1.0 - t)) as u8, (255.0 * (1.0 - t)) as u8)
        } else {
            RGBColor((255.0 * (1.0 + t)) as u8, (255.0 * (1.0 + t)) as u8, 255)
        }
    };
    top(
        &panels[3],
        "top, fitted points (colour: z − f, blue −5 mm … red +5 mm)",
        &p.smoothed,
        residual,
        (xr, yr),
    )?;
    root.present().map_err(err)
}
