//! The picture of one planned dig: the pile's section along the dipper's
//! lane with the tooth path (and the dipper at the end of the dig), and the
//! hoist and crowd forces over time against their ratings.

use crate::error::Error;
use infer::PileSurface;
use infer::rope_shovel::{ShovelParams, ShovelSample};
use plotters::prelude::*;
use std::path::Path;

fn err(path: &Path) -> impl Fn(&dyn std::fmt::Display) -> Error + '_ {
    move |e| Error::Plot {
        path: path.to_path_buf(),
        detail: e.to_string(),
    }
}

type Chart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// Draws a chart's legend in its upper left corner.
fn legend<'a, 'b: 'a>(chart: &mut Chart<'a, 'b>) -> Result<(), String> {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperLeft)
        .draw()
        .map_err(|e| e.to_string())
}

/// Writes the two-panel SVG of a dig's `samples` on `surface` to `path`.
pub fn write_svg(
    path: &Path,
    title: &str,
    params: &ShovelParams,
    surface: &PileSurface,
    samples: &[ShovelSample],
) -> Result<(), Error> {
    let e = err(path);
    let root = SVGBackend::new(path, (1000, 900)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let root = root.titled(title, ("sans-serif", 18)).map_err(|x| e(&x))?;
    let (upper, lower) = root.split_vertically(520);
    let d = surface.domain;
    let y = params.lane_y;
    let mut section = ChartBuilder::on(&upper)
        .caption(
            format!("pile section at y = {y:.3} m and the tooth path"),
            ("sans-serif", 16),
        )
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(50)
        .build_cartesian_2d(d.x[0] - 0.05..d.x[1], -0.02..0.5)
        .map_err(|x| e(&x))?;
    section
        .configure_mesh()
        .x_desc("x from the toe (m)")
        .y_desc("z (m)")
        .draw()
        .map_err(|x| e(&x))?;
    let brown = RGBColor(150, 100, 40);
    let xs = (0..=200).map(|i| d.x[0] + (d.x[1] - d.x[0]) * i as f64 / 200.0);
    section
        .draw_series(LineSeries::new(
            xs.filter_map(|x| surface.height(x, y).ok().map(|z| (x, z))),
            brown.stroke_width(2),
        ))
        .map_err(|x| e(&x))?
        .label(format!("perceived surface (R² {:.4})", surface.r_squared))
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], brown.stroke_width(2)));
    section
        .draw_series(LineSeries::new(
            samples.iter().map(|s| (s.tip[0], s.tip[1])),
            BLUE.stroke_width(2),
        ))
        .map_err(|x| e(&x))?
        .label("tooth tip path")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], BLUE.stroke_width(2)));
    section
        .draw_series(
            samples
                .iter()
                .step_by(10)
                .map(|s| Circle::new((s.tip[0], s.tip[1]), 3, BLUE.filled())),
        )
        .map_err(|x| e(&x))?
        .label("every 10th time sample");
    legend(&mut section).map_err(|x| e(&x))?;

    let t_end = samples.last().map_or(1.0, |s| s.t).max(1e-9);
    let f_max = params.max_force[0].max(params.max_force[1]) * 1.1;
    let f_min = samples
        .iter()
        .flat_map(|s| s.force)
        .fold(0.0f64, f64::min)
        .max(-f_max)
        - 10.0;
    let mut forces = ChartBuilder::on(&lower)
        .caption("hoist and crowd forces", ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..t_end, f_min..f_max)
        .map_err(|x| e(&x))?;
    forces
        .configure_mesh()
        .x_desc("t (s)")
        .y_desc("force (N)")
        .draw()
        .map_err(|x| e(&x))?;
    let green = RGBColor(30, 150, 30);
    for (i, (name, colour)) in [("hoist", RED), ("crowd", green)].into_iter().enumerate() {
        forces
            .draw_series(LineSeries::new(
                samples.iter().map(|s| (s.t, s.force[i])),
                colour.stroke_width(2),
            ))
            .map_err(|x| e(&x))?
            .label(format!("{name} force"))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], colour.stroke_width(2)));
        let rated = params.max_force[i];
        forces
            .draw_series(LineSeries::new(
                [(0.0, rated), (t_end, rated)],
                colour.mix(0.5).stroke_width(1),
            ))
            .map_err(|x| e(&x))?
            .label(format!("{name} rating {rated:.0} N"));
    }
    legend(&mut forces).map_err(|x| e(&x))?;
    root.present().map_err(|x| e(&x))
}
