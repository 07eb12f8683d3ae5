//! Exercises infer's evaluation path from a `no_std` crate.
#![no_std]

use infer::{CarveBuffer, Config, DigParams, DigQuery, DigType, Ground, Pose, Terrain};

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {}
}

/// Objective of the reference dig, or −1 on error; a C caller can link it.
#[unsafe(no_mangle)]
pub extern "C" fn infer_reference_objective() -> f64 {
    let cfg = Config::default();
    let start = Pose { x: 1.0, y: -0.25, zeta: infer::deg(-90.0) };
    let end = Pose { x: 0.7, y: -0.2, zeta: infer::deg(160.0) };
    let Ok(q) = DigQuery::from_poses(&cfg, &start, &end, cfg.ground_level, DigType::Downward) else { return -1.0 };
    let Ok(terrain) = Terrain::flat(-1.5, 1.5, cfg.terrain_dx, q.surface) else { return -1.0 };
    let mut buf = CarveBuffer::default();
    let y = DigParams::from_array([4.469e-5, 4.926e-5, 1.0e-7, 7.011]);
    match infer::evaluate(&cfg, &q.task(), &y, Ground { terrain: &terrain, base_x: 0.0 }, &mut buf) {
        Ok(r) => r.objective,
        Err(_) => -1.0,
    }
}

/// Digs of task A planned with a fixed Y through the planner's no-heap step
/// API, or −1 on a bad task; shows the planner builds without `std`.
#[unsafe(no_mangle)]
pub extern "C" fn infer_plan_task_a_digs() -> i32 {
    struct Fixed;
    impl infer::DigPredictor for Fixed {
        fn predict(&mut self, _: &DigQuery, _: Ground<'_>) -> Result<DigParams, infer::Error> {
            Ok(DigParams::from_array([4.469e-5, 4.926e-5, 1.0e-7, 7.011]))
        }
    }
    let cfg = Config::default();
    let Ok(planner) = infer::Planner::new(&cfg, &infer::PlannerSettings::default()) else { return -1 };
    let Some(task) = infer::TrenchTask::reference('A') else { return -1 };
    let Ok(mut state) = planner.start(&task) else { return -1 };
    let mut n = 0;
    while let Ok(Some(_)) = planner.next_dig(&mut state, &mut Fixed) {
        n += 1;
    }
    n
}

/// Digs of task A planned from one template (its own first dig twice, a
/// made-up plan) through the template planner, or −1 when it says it
/// cannot; shows the template planner builds without `std`. Its work
/// lives in a static-sized value the caller owns.
#[unsafe(no_mangle)]
pub extern "C" fn infer_template_task_a_digs() -> i32 {
    let cfg = Config::default();
    let Ok(planner) = infer::Planner::new(&cfg, &infer::PlannerSettings::default()) else { return -1 };
    let Some(task) = infer::TrenchTask::reference('A') else { return -1 };
    // Ten spec variables, then the three skews (0: the spec's family).
    let dig = [0.25, 1.04, 0.3, 0.05, infer::deg(-90.0), infer::deg(160.0), 0.0, 0.0, 0.0, 7.0, 0.0, 0.0, 0.0];
    let Ok(template) = infer::Template::new(task, &[dig, dig]) else { return -1 };
    let Ok(mut work) = infer::TemplateWork::new(&planner) else { return -1 };
    let settings = infer::TemplateSettings { max_evaluations: 100, ..Default::default() };
    match work.plan(&planner, &task, infer::SeedTemplates::same(&[template]), &settings) {
        Ok(()) => work.len() as i32,
        Err(_) => -1,
    }
}

/// Height of a tilted-plane pile surface at its centre, or −1 on error;
/// shows the perceived pile surface evaluates without `std`.
#[unsafe(no_mangle)]
pub extern "C" fn infer_pile_height_at_centre() -> f64 {
    let Ok(domain) = infer::PileDomain::new([0.0, 0.5], [-0.25, 0.25]) else { return -1.0 };
    let mut c = [[0.0; infer::pile::PILE_GRID]; infer::pile::PILE_GRID];
    for (j, row) in c.iter_mut().enumerate() {
        for (k, v) in row.iter_mut().enumerate() {
            *v = 0.84 * domain.control_point(j, k)[0];
        }
    }
    let Ok(s) = infer::PileSurface::new(domain, c, 1.0) else { return -1.0 };
    s.height(0.25, 0.0).unwrap_or(-1.0)
}

/// A crawler move planned by the improved potential field around one rock
/// into a caller-owned buffer, then one fuzzy controller output; returns
/// the path's point count, or −1 on error. Shows `infer::crawler` builds
/// without `std` or a heap.
#[unsafe(no_mangle)]
pub extern "C" fn infer_crawler_plan_points() -> i32 {
    use infer::crawler::field::{plan, FieldParams, Method};
    let Ok(rock) = infer::crawler::Obstacle::circle([10.0, 0.3], 1.5) else { return -1 };
    let mut path = [[0.0; 2]; 1024];
    let f = FieldParams::default();
    let u = infer::crawler::fuzzy::infer(0.1, -3.0);
    match plan(Method::Improved, [0.0, 0.0], [20.0, 0.0], [1.0, 0.0], &[rock], &f, &mut path) {
        Ok(raw) if u.is_finite() => raw.len as i32,
        _ => -1,
    }
}

/// 1 when the roadheader's head at (θ1 −90°, θ2 −30°, d 0.25 m) is a
/// cuttable point of the source's left half-section, 0 when not, −1 on
/// bad input; shows the roadheader's kinematics build without `std`.
#[unsafe(no_mangle)]
pub extern "C" fn infer_roadheader_cuttable() -> i32 {
    use infer::roadheader::{Joints, Placement, Roadheader, Section, Side};
    let Ok(section) = Section::rectangle(5.0, 3.0, 20.0, 1.0) else { return -1 };
    let machine = Roadheader::facing(&section);
    let q = Joints { theta1: infer::deg(-90.0), theta2: infer::deg(-30.0), d: 0.25 };
    match machine.forward(&q) {
        Ok(pose) => (section.half(Side::Left).place(&machine.head, &pose) == Placement::Cuttable) as i32,
        Err(_) => -1,
    }
}

/// f1 (J/kg) of the source's typical rope shovel optimum on the analytic
/// typical pile, or −1 on error; shows the shovel model builds without `std`.
#[unsafe(no_mangle)]
pub extern "C" fn infer_shovel_typical_f1() -> f64 {
    use infer::rope_shovel::{self, DigVars, ShovelParams, volume::typical_pile};
    let Ok(surface) = typical_pile(0.4, infer::deg(40.0)) else { return -1.0 };
    match rope_shovel::evaluate(&ShovelParams::default(), &surface, &DigVars::TYPICAL) {
        Ok(r) => r.f1,
        Err(_) => -1.0,
    }
}
