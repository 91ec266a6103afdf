//! The sonar simulator: floor plans (`sonarmap-plan` v1), a beam model of the Polaroid 6500 and
//! seeded noise. Pure: plans come in as bytes, runs go out as values.

mod beam;
mod building;
mod families;
mod odometry;
mod pace;
mod plan;
mod simulate;

pub use beam::{Hit, Model, World};
pub use building::{building_plan, BuildingSpec};
pub use families::{family_plan, repeat_laps, SceneKind};
pub use odometry::{with_odometry, OdometryError};
pub use pace::{pose_at, resample_path, Pace};
pub use plan::{
    interpolate_path, load_plan, plan_from_file, plan_to_file, Plan, PlanFile, SimFile,
    SimSettings, DEFAULT_ROUGHNESS_DEG, MAX_BOUNCES, PLAN_FORMAT,
};
pub use simulate::{simulate, simulate_paced};
