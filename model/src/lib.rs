//! The burn side of the dig planner: the network that maps a dig query to a
//! trajectory (`network`) and the physics of `infer` in differentiable tensor
//! form for the physics-informed losses (`physics`).

pub mod dense;
pub mod network;
pub mod physics;
pub mod task_net;
