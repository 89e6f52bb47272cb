//! `footslam view`: an interactive map page of one run folder or several.

use super::common::{output_dir, parse_extent};
use anyhow::{Result, bail};
use footslam::view::{
    Basemap, Page, ViewRun, read_run, read_truth_layer, read_waypoints_layer, write_page,
};
use std::path::PathBuf;

/// Arguments of `footslam view`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Run folders to show (what learn, track, survey, simulate, plan or import wrote, with
    /// their walk-N/ folders); several are shown side by side, each layer named after its
    /// folder.
    #[arg(required = true, value_name = "RUN_FOLDER")]
    runs: Vec<PathBuf>,
    /// Ground truth `t,x,y[,z,level]` (local metres of the first run's frame, e.g. the
    /// simulator's truth.csv) to show over the runs; repeat for several. A run folder's own
    /// truth.csv is shown without it.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    truth: Vec<PathBuf>,
    /// Sparse ground truth `t,x,y[,level]` (local metres of the first run's frame, e.g. an
    /// importer's waypoints.csv); repeat for several.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    waypoints: Vec<PathBuf>,
    /// Web map tiles under the layers: a URL template such as
    /// `https://tile.openstreetmap.org/{z}/{x}/{y}.png` (the page then fetches tiles when
    /// opened; none by default). The runs must have their real origin (`--origin`).
    #[arg(
        long,
        value_name = "URL",
        conflicts_with = "basemap_image",
        help_heading = "Basemap"
    )]
    basemap: Option<String>,
    /// The attribution the tiles' licence asks for, shown in the corner.
    #[arg(
        long,
        value_name = "TEXT",
        requires = "basemap",
        default_value = "",
        help_heading = "Basemap"
    )]
    basemap_attribution: String,
    /// An image (PNG, JPEG, GIF, WebP or SVG; e.g. a floor plan) under the layers, copied
    /// beside the page and stretched over `--basemap-extent`.
    #[arg(
        long,
        value_name = "FILE",
        requires = "basemap_extent",
        help_heading = "Basemap"
    )]
    basemap_image: Option<PathBuf>,
    /// Where `--basemap-image` lies: `X0,Y0,X1,Y1` (west, south, east, north) in local
    /// metres of the first run's frame.
    #[arg(
        long,
        value_name = "X0,Y0,X1,Y1",
        value_parser = parse_extent,
        allow_hyphen_values = true,
        requires = "basemap_image",
        help_heading = "Basemap"
    )]
    basemap_extent: Option<[f64; 4]>,
    /// Output folder: index.html with data.js, the viewer's script and Leaflet beside it
    /// (default: a new folder under `outputs/`).
    #[arg(short = 'o', long, value_name = "DIR", help_heading = "Outputs")]
    out: Option<PathBuf>,
}

/// Runs `footslam view`.
pub fn run(args: Args) -> Result<()> {
    let mut runs = args
        .runs
        .iter()
        .map(|folder| read_run(folder))
        .collect::<footslam::Result<Vec<ViewRun>>>()?;
    add_references(&mut runs[0], &args)?;
    let basemap = basemap(&args, &runs[0])?;
    let page = Page::new(runs, basemap);
    let mut folder = super::common::create_run_folder(&output_dir(args.out.clone(), "view"))?;
    folder.protect(page.inputs());
    write_page(&folder, &page)?;
    folder.write_json("summary.json", &page.summary())?;
    let out = folder.commit()?;
    for run in &page.runs {
        let names: Vec<&str> = run.layers.iter().map(|l| l.name.as_str()).collect();
        info!("{}: {} layers: {}", run.name, names.len(), names.join(", "));
    }
    info!("open {} in a browser", out.join("index.html").display());
    super::verbosity::done(&out, None);
    Ok(())
}

/// `--truth` and `--waypoints`, as layers of the first run (in its frame).
fn add_references(run: &mut ViewRun, args: &Args) -> Result<()> {
    for path in &args.truth {
        run.layers.push(read_truth_layer(path, &run.origin)?);
        run.inputs.push(path.clone());
    }
    for path in &args.waypoints {
        run.layers.push(read_waypoints_layer(path, &run.origin)?);
        run.inputs.push(path.clone());
    }
    Ok(())
}

/// The basemap of `--basemap` or `--basemap-image`, if any.
fn basemap(args: &Args, first: &ViewRun) -> Result<Option<Basemap>> {
    Ok(
        match (&args.basemap, &args.basemap_image, args.basemap_extent) {
            (Some(url), _, _) => Some(Basemap::tiles(url, &args.basemap_attribution)?),
            (None, Some(image), Some(extent)) => {
                Some(Basemap::image(image, extent, &first.origin)?)
            }
            (None, Some(_), None) => bail!("--basemap-image needs --basemap-extent X0,Y0,X1,Y1"),
            (None, None, _) => None,
        },
    )
}
