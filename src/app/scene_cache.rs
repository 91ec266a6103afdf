//! The map view's scene between frames: built again only when what it shows changes (the
//! snapshot, the selection, the layers, the zoom by more than a level of detail, or the view
//! leaving the region the scene was built for), so a frame spent looking, hovering or panning a
//! little costs the drawing alone, whatever the map's size.

use crate::scene::{LayerSet, Scene, SceneId, ViewOptions, ViewRect};
use std::sync::Arc;

/// Zoom steps between levels of detail: the scene is rebuilt when the view's scale changes by
/// more than 2^(1/LOD_STEPS_PER_OCTAVE).
const LOD_STEPS_PER_OCTAVE: f64 = 2.0;

/// How far the region a scene is built for reaches beyond the visible rectangle, in
/// visible widths (heights) on each side: panning within it reuses the scene.
const REGION_MARGIN: f64 = 0.5;

/// What a scene shows, apart from the view.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSubject {
    /// Which replay (or baseline) and step: any value that changes with them.
    pub source: (u64, usize),
    /// The selection (its supporting readings are drawn).
    pub selection: SceneId,
    /// The layers on.
    pub layers: LayerSet,
    /// Whether the truth layer's verdicts are present.
    pub truth: bool,
}

#[derive(Clone, Debug, PartialEq)]
struct Key {
    subject: SceneSubject,
    lod_level: i64,
    region_m: Option<[f64; 4]>,
}

/// The last scene built, with what it was built for.
#[derive(Debug, Default)]
pub struct SceneCache {
    last: Option<(Key, Arc<Scene>)>,
    builds: usize,
}

impl SceneCache {
    /// The scene of `subject` for a view showing `visible_m` at `world_per_px` (0 before the
    /// first frame: no level of detail, no region): the last one when it still serves, else
    /// `build(options)`.
    pub fn scene(
        &mut self,
        subject: SceneSubject,
        visible_m: Option<ViewRect>,
        world_per_px: f64,
        build: impl FnOnce(&ViewOptions) -> Scene,
    ) -> Arc<Scene> {
        let lod_level = lod_level(world_per_px);
        if let Some((key, scene)) = &self.last {
            let region_serves = match (key.region_m, visible_m) {
                (None, _) => true,
                (Some([x0, y0, x1, y1]), Some(v)) => {
                    x0 <= v.min.x && y0 <= v.min.y && x1 >= v.max.x && y1 >= v.max.y
                }
                (Some(_), None) => false,
            };
            if key.subject == subject && key.lod_level == lod_level && region_serves {
                return Arc::clone(scene);
            }
        }
        let region_m = visible_m.filter(|_| world_per_px > 0.0).map(|v| {
            let (dx, dy) = (v.width_m() * REGION_MARGIN, v.height_m() * REGION_MARGIN);
            [v.min.x - dx, v.min.y - dy, v.max.x + dx, v.max.y + dy]
        });
        // The level's own scale (its finest), so the scene is the same at every zoom within it.
        let options = ViewOptions {
            layers: subject.layers,
            world_per_px: lod_scale(lod_level, world_per_px),
            visible_m: region_m,
        };
        let scene = Arc::new(build(&options));
        self.builds += 1;
        self.last = Some((
            Key {
                subject,
                lod_level,
                region_m,
            },
            Arc::clone(&scene),
        ));
        scene
    }

    /// Scenes built so far (a frame that reused one built none).
    pub fn builds(&self) -> usize {
        self.builds
    }
}

/// The level of detail of a scale: `world_per_px` rounded down to a power of
/// 2^(1/LOD_STEPS_PER_OCTAVE); `i64::MIN` for no level (a scale of 0).
fn lod_level(world_per_px: f64) -> i64 {
    if world_per_px > 0.0 && world_per_px.is_finite() {
        (world_per_px.log2() * LOD_STEPS_PER_OCTAVE).floor() as i64
    } else {
        i64::MIN
    }
}

/// The scale of level `level` (0 for no level).
fn lod_scale(level: i64, world_per_px: f64) -> f64 {
    if level == i64::MIN {
        0.0
    } else {
        (level as f64 / LOD_STEPS_PER_OCTAVE)
            .exp2()
            .min(world_per_px)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;

    fn subject(step: usize) -> SceneSubject {
        SceneSubject {
            source: (1, step),
            selection: SceneId::None,
            layers: LayerSet::all(),
            truth: false,
        }
    }

    fn view(x0: f64, width: f64) -> Option<ViewRect> {
        Some(ViewRect::new(
            Point::new(x0, 0.0),
            Point::new(x0 + width, width),
        ))
    }

    #[test]
    fn a_scene_is_built_again_only_when_what_it_shows_changes() {
        let mut cache = SceneCache::default();
        let mut seen: Vec<ViewOptions> = Vec::new();
        let mut get = |cache: &mut SceneCache, s, v, wpp| {
            cache.scene(s, v, wpp, |o: &ViewOptions| {
                seen.push(*o);
                Scene::default()
            });
        };
        get(&mut cache, subject(0), view(0.0, 10.0), 0.01);
        // The same view, a small pan, a zoom within the level: reused.
        get(&mut cache, subject(0), view(0.0, 10.0), 0.01);
        get(&mut cache, subject(0), view(3.0, 10.0), 0.01);
        get(&mut cache, subject(0), view(3.0, 10.0), 0.0105);
        assert_eq!(cache.builds(), 1);
        // Panned past the region (5 m margin), zoomed out a level, another step, another
        // selection: built again.
        get(&mut cache, subject(0), view(6.0, 10.0), 0.0105);
        get(&mut cache, subject(0), view(6.0, 10.0), 0.02);
        get(&mut cache, subject(1), view(6.0, 10.0), 0.02);
        let mut selected = subject(1);
        selected.selection = SceneId::MapSegment(3);
        get(&mut cache, selected, view(6.0, 10.0), 0.02);
        assert_eq!(cache.builds(), 5);
        // The region reaches half a view beyond each side; the scale is the level's finest.
        assert_eq!(seen[0].visible_m, Some([-5.0, -5.0, 15.0, 15.0]));
        assert!(seen[0].world_per_px <= 0.01 && seen[0].world_per_px > 0.01 / 2f64.sqrt());
    }

    #[test]
    fn before_the_first_frame_the_whole_scene_is_built_without_level_of_detail() {
        let mut cache = SceneCache::default();
        let mut options = None;
        cache.scene(subject(0), None, 0.0, |o: &ViewOptions| {
            options = Some(*o);
            Scene::default()
        });
        let o = options.unwrap();
        assert_eq!((o.world_per_px, o.visible_m), (0.0, None));
        // A later frame with a view builds for it.
        cache.scene(subject(0), view(0.0, 1.0), 0.001, |_| Scene::default());
        assert_eq!(cache.builds(), 2);
    }
}
