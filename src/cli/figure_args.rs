//! The figure options of `run --svg` (docs/formats.md §10): the region, the layers, the page
//! size, the figure style and a PNG beside the SVG, so a figure made in the app can be made
//! again from the command line.

use anyhow::{anyhow, bail, Result};
use clap::Args;
use sonarmap::replay::StepView;
use sonarmap::run::Run;
use sonarmap::scene::figure::{figure_svg, Figure};
use sonarmap::scene::{Layer, LayerSet, SceneId, SceneInput, ViewRect};
use std::path::{Path, PathBuf};

/// The default page, pixels.
const DEFAULT_SIZE_PX: (u32, u32) = (1000, 700);

/// How `run --svg` draws its figure.
#[derive(Debug, Args, Clone, Default)]
pub struct FigureArgs {
    /// With --svg: the region shown, X0,Y0,X1,Y1 in the log's units (default: the content).
    #[arg(long, value_name = "X0,Y0,X1,Y1")]
    pub view: Option<String>,
    /// With --svg: the layers drawn, comma-separated names (e.g. floor-plan,map,labels;
    /// default: the paper figure's).
    #[arg(long, value_name = "L1,L2,...")]
    pub layers: Option<String>,
    /// With --svg: the page size in pixels, WxH (default 1000x700).
    #[arg(long, value_name = "WxH")]
    pub size: Option<String>,
    /// With --svg: also write the figure as a PNG beside the SVG (V.png), rendered with resvg
    /// at the page size.
    #[arg(long)]
    pub png: bool,
    /// With --svg: the figure style (map labels only where this snapshot's decisions met the
    /// map).
    #[arg(long)]
    pub figure: bool,
}

/// A figure's options, checked.
#[derive(Clone, Debug, PartialEq)]
pub struct FigureSpec {
    view_units: Option<[f64; 4]>,
    layers: LayerSet,
    size_px: (u32, u32),
    png: bool,
    figure_style: bool,
}

impl FigureArgs {
    /// True when any figure option is given.
    pub fn any(&self) -> bool {
        self.view.is_some()
            || self.layers.is_some()
            || self.size.is_some()
            || self.png
            || self.figure
    }

    /// The options checked; an error names the option and what was expected. `default_layers`
    /// when --layers is not given.
    pub fn spec(&self, default_layers: LayerSet) -> Result<FigureSpec> {
        let view_units = match &self.view {
            None => None,
            Some(text) => {
                let v: Vec<f64> = text
                    .split(',')
                    .map(|t| t.trim().parse::<f64>())
                    .collect::<Result<_, _>>()
                    .map_err(|_| anyhow!("--view {text:?}: expected four numbers X0,Y0,X1,Y1"))?;
                match v[..] {
                    [x0, y0, x1, y1]
                        if v.iter().all(|x| x.is_finite()) && x0 < x1 && y0 < y1 =>
                    {
                        Some([x0, y0, x1, y1])
                    }
                    _ => bail!(
                        "--view {text:?}: expected four finite numbers X0,Y0,X1,Y1 with X0 < X1 and Y0 < Y1"
                    ),
                }
            }
        };
        let layers = match &self.layers {
            None => default_layers,
            Some(text) => {
                let mut set = LayerSet::empty();
                for name in text.split(',').map(str::trim).filter(|n| !n.is_empty()) {
                    let layer = Layer::from_name(name).ok_or_else(|| {
                        let known: Vec<&str> = Layer::ALL.iter().map(|l| l.name()).collect();
                        anyhow!(
                            "--layers: no layer {name:?}; the layers are {}",
                            known.join(", ")
                        )
                    })?;
                    set.set(layer, true);
                }
                set
            }
        };
        let size_px = match &self.size {
            None => DEFAULT_SIZE_PX,
            Some(text) => {
                let parts: Vec<&str> = text.split(['x', 'X', '×']).collect();
                match parts[..] {
                    [w, h] => match (w.trim().parse::<u32>(), h.trim().parse::<u32>()) {
                        (Ok(w), Ok(h))
                            if (100..=16_384).contains(&w) && (100..=16_384).contains(&h) =>
                        {
                            (w, h)
                        }
                        _ => bail!("--size {text:?}: expected WxH, each 100 to 16384 pixels"),
                    },
                    _ => bail!("--size {text:?}: expected WxH, e.g. 1600x1000"),
                }
            }
        };
        Ok(FigureSpec {
            view_units,
            layers,
            size_px,
            png: self.png,
            figure_style: self.figure,
        })
    }
}

/// The layers of a paper figure: ground truth, both snapshots' points, balls, fitted and map
/// segments, updates, decisions, correlations, the robot and labels; no beams or discarded
/// readings (they would dwarf the room).
pub fn paper_figure_layers() -> LayerSet {
    LayerSet::all()
        .with(Layer::Beams, false)
        .with(Layer::Discarded, false)
        .with(Layer::MapBefore, false)
        .with(Layer::Clusters, false)
}

/// The SVG of `view` (a snapshot of `run`) as a paper figure (the whole content in view, the
/// paper figure's layers, 1000×700 pixels, labels decluttered for the page).
pub fn paper_figure_svg(run: &Run, view: &StepView) -> String {
    FigureArgs::default()
        .spec(paper_figure_layers())
        .expect("the default figure options are valid")
        .svg(run, view)
}

impl FigureSpec {
    /// The figure of `view` (a snapshot of `run`) as SVG.
    pub fn svg(&self, run: &Run, view: &StepView) -> String {
        let m = run.units.metres_per_unit();
        let figure = Figure {
            view: self.view_units.map(|[x0, y0, x1, y1]| {
                ViewRect::new(
                    sonarmap::geometry::Point::new(x0 * m, y0 * m),
                    sonarmap::geometry::Point::new(x1 * m, y1 * m),
                )
            }),
            layers: self.layers,
            size_px: self.size_px,
            selection: SceneId::None,
            figure_style: self.figure_style,
            title: format!("{} — snapshot {}", run.name, view.index),
        };
        figure_svg(&SceneInput::from_view(run, view), &figure, run.units)
    }

    /// Where the PNG goes when asked for: beside `svg_path`, with the extension `png`.
    pub fn png_path(&self, svg_path: &Path) -> Option<PathBuf> {
        self.png.then(|| svg_path.with_extension("png"))
    }

    /// The page width, pixels (the PNG's).
    pub fn width_px(&self) -> u32 {
        self.size_px.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_parse_and_bad_ones_name_the_option() {
        let args = FigureArgs {
            view: Some("0,0,200,150".into()),
            layers: Some("floor-plan,map,labels".into()),
            size: Some("1600x1000".into()),
            png: true,
            figure: true,
        };
        let spec = args.spec(LayerSet::all()).unwrap();
        assert_eq!(spec.size_px, (1600, 1000));
        assert_eq!(spec.view_units, Some([0.0, 0.0, 200.0, 150.0]));
        assert!(spec.layers.contains(Layer::Labels) && !spec.layers.contains(Layer::Beams));
        assert_eq!(
            spec.png_path(Path::new("a/b.svg")),
            Some(PathBuf::from("a/b.png"))
        );
        for (bad, needle) in [
            (
                FigureArgs {
                    view: Some("0,0,1".into()),
                    ..Default::default()
                },
                "--view",
            ),
            (
                FigureArgs {
                    view: Some("5,0,1,1".into()),
                    ..Default::default()
                },
                "X0 < X1",
            ),
            (
                FigureArgs {
                    layers: Some("map,walls".into()),
                    ..Default::default()
                },
                "walls",
            ),
            (
                FigureArgs {
                    size: Some("10x10".into()),
                    ..Default::default()
                },
                "--size",
            ),
        ] {
            let e = bad.spec(LayerSet::all()).unwrap_err().to_string();
            assert!(e.contains(needle), "{e}");
        }
    }
}
