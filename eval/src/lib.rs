//! Comparisons of the learned planner with the optimiser baselines, reports
//! and benchmarks (issue 6). Not built yet: the crate exists so the
//! workspace has its final shape; today the per-crate benches
//! (`cargo bench -p infer`, `cargo bench -p dataset_gen`) and the training
//! reports in `artifacts/` hold the measurements.
