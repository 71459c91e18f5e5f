// SPDX-License-Identifier: MIT OR Apache-2.0
//! The latency plot of a comparison, drawn as cyclictest's users draw theirs: x = latency
//! in µs, y = count on a log scale, one line per measurement, one panel per group (wake-up,
//! busy-polling, sleeping) so that each figure sits beside its own limit at a readable scale.
//!
//! SVG only: plotters' SVG backend writes text as `<text>` elements and sizes it with a
//! built-in estimate, so it needs no font files or system libraries on a fresh machine.

use plotters::prelude::*;
use procimg_control::Bucket;
use std::path::Path;

/// One line of a panel.
pub struct Series {
    /// Legend text.
    pub label: String,
    /// The histogram.
    pub buckets: Vec<Bucket>,
    /// 99.9th percentile, ns (sets the x range).
    pub p999_ns: u64,
    /// Largest value, ns.
    pub max_ns: u64,
    /// A limit (drawn dashed-looking: thinner) rather than a figure.
    pub baseline: bool,
}

/// One panel.
pub struct Panel {
    /// Caption.
    pub title: String,
    /// Its lines; a panel without any says "not measured".
    pub series: Vec<Series>,
    /// Narrowest bin, µs: 1 for a panel with cyclictest, whose histogram has 1 µs buckets
    /// (narrower bins would draw it as isolated dashes).
    pub min_bin_us: f64,
}

/// Why the plot could not be drawn.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// plotters failed (usually: the file could not be written).
    #[error("cannot draw {path}: {detail}; check that its directory is writable")]
    Draw {
        /// The file.
        path: String,
        /// What failed.
        detail: String,
    },
}

/// Bins across the x axis: fine enough to show a distribution's shape, coarse enough that
/// a few thousand values still draw a line and not scattered dots.
const BINS: usize = 150;

/// Line colours: figures and their limits alternate, so the palette is ordered in pairs of
/// a strong and a muted colour.
const COLOURS: [RGBColor; 6] = [
    RGBColor(0xd6, 0x27, 0x28),
    RGBColor(0x1f, 0x77, 0xb4),
    RGBColor(0x2c, 0xa0, 0x2c),
    RGBColor(0x94, 0x67, 0xbd),
    RGBColor(0xff, 0x7f, 0x0e),
    RGBColor(0x8c, 0x56, 0x4b),
];

/// The x range of a panel in µs: up to the largest value, but no further than four times
/// the largest 99.9th percentile, so that one outlier does not squeeze everything into the
/// first bins. Longer values are counted in the last bin, and the caption says so.
fn x_max_us(series: &[Series]) -> (f64, bool) {
    let max = series.iter().map(|s| s.max_ns).max().unwrap_or(1);
    let p999 = series.iter().map(|s| s.p999_ns).max().unwrap_or(1);
    let cap = p999.saturating_mul(4).max(1);
    let clipped = max > cap;
    ((max.min(cap) as f64 / 1000.0 * 1.05).max(0.01), clipped)
}

/// Consecutive non-empty bins: (bin centre µs, count).
type Run = Vec<(f64, u64)>;

/// The buckets re-binned into `BINS` equal bins over 0..x_max µs, as runs of consecutive
/// non-empty bins: (bin centre µs, count). A log axis has no zero, so an empty bin breaks
/// the line instead of being drawn across; a run of one bin becomes a flat dash across
/// its width, so it still shows.
fn binned(buckets: &[Bucket], x_max: f64, min_bin_us: f64) -> Vec<Run> {
    let width = (x_max / BINS as f64).max(min_bin_us);
    let bins = ((x_max / width).ceil() as usize).clamp(1, BINS);
    let mut counts = vec![0u64; bins];
    for b in buckets {
        let i = ((b.ns as f64 / 1000.0) / width) as usize;
        counts[i.min(bins - 1)] += b.count;
    }
    let mut runs: Vec<Run> = Vec::new();
    let mut run = Vec::new();
    for (i, &c) in counts.iter().enumerate() {
        if c > 0 {
            run.push(((i as f64 + 0.5) * width, c));
        } else if !run.is_empty() {
            runs.push(std::mem::take(&mut run));
        }
    }
    if !run.is_empty() {
        runs.push(run);
    }
    for run in &mut runs {
        if let [(x, c)] = run[..] {
            *run = vec![(x - width / 2.0, c), (x + width / 2.0, c)];
        }
    }
    runs
}

/// Draws `panels` one above the other into the SVG file `path`.
pub fn latency_svg(path: &Path, title: &str, panels: &[Panel]) -> Result<(), PlotError> {
    draw(path, title, panels).map_err(|detail| PlotError::Draw {
        path: path.display().to_string(),
        detail,
    })
}

fn draw(path: &Path, title: &str, panels: &[Panel]) -> Result<(), String> {
    let height = 60 + 380 * panels.len().max(1) as u32;
    let root = SVGBackend::new(path, (1000, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let root = root
        .titled(title, ("sans-serif", 22))
        .map_err(|e| e.to_string())?;
    let areas = root.split_evenly((panels.len().max(1), 1));
    for (area, panel) in areas.iter().zip(panels) {
        draw_panel(area, panel)?;
    }
    root.present().map_err(|e| e.to_string())
}

fn draw_panel(
    area: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    panel: &Panel,
) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let (x_max, clipped) = x_max_us(&panel.series);
    let lines: Vec<(&Series, Vec<Run>)> = panel
        .series
        .iter()
        .map(|s| (s, binned(&s.buckets, x_max, panel.min_bin_us)))
        .collect();
    let y_max = lines
        .iter()
        .flat_map(|(_, runs)| runs.iter().flatten().map(|p| p.1))
        .max()
        .unwrap_or(1);
    let caption = match (panel.series.is_empty(), clipped) {
        (true, _) => format!("{}: not measured", panel.title),
        (false, true) => format!("{} (longer values in the last bin)", panel.title),
        (false, false) => panel.title.clone(),
    };
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 17))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(
            0f64..x_max,
            (1u64..y_max.saturating_mul(3).max(10)).log_scale(),
        )
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc("latency (µs)")
        .y_desc("count")
        .draw()
        .map_err(|e| err(&e))?;
    for (i, (s, runs)) in lines.into_iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let style = colour.stroke_width(if s.baseline { 1 } else { 2 });
        chart
            .draw_series(runs.into_iter().map(|run| PathElement::new(run, style)))
            .map_err(|e| err(&e))?
            .label(s.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
    }
    if !panel.series.is_empty() {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| err(&e))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_hold_every_value_and_outliers_land_in_the_last() {
        let buckets = vec![
            Bucket {
                ns: 1_000,
                count: 5,
            },
            Bucket {
                ns: 2_000,
                count: 3,
            },
            Bucket {
                ns: 900_000,
                count: 1,
            },
        ];
        let runs = binned(&buckets, 3.0, 0.0);
        // 1 µs and 2 µs are separate runs; the outlier is a dash at the end of the axis.
        assert_eq!(runs.len(), 3);
        assert!(runs.iter().all(|r| r.len() == 2));
        assert_eq!(runs.iter().map(|r| r[0].1).sum::<u64>(), 9);
        assert!(runs[2][1].0 > 2.99);
    }

    #[test]
    fn an_svg_is_written_without_fonts() {
        let path = std::env::temp_dir().join(format!("procimg-plot-{}.svg", std::process::id()));
        let series = |label: &str, ns: u64, baseline| Series {
            label: label.into(),
            buckets: vec![
                Bucket { ns, count: 100 },
                Bucket {
                    ns: ns * 2,
                    count: 3,
                },
            ],
            p999_ns: ns * 2,
            max_ns: ns * 2,
            baseline,
        };
        let panels = [
            Panel {
                title: "wake-up".into(),
                min_bin_us: 1.0,
                series: vec![
                    series("figure-a", 10_000, false),
                    series("limit-b", 9_000, true),
                ],
            },
            Panel {
                title: "busy".into(),
                min_bin_us: 0.0,
                series: vec![],
            },
        ];
        latency_svg(&path, "test", &panels).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert!(text.trim_start().starts_with("<svg"), "{}", &text[..100]);
        assert!(text.contains("figure-a"), "legend text missing");
        assert!(text.contains("not measured"));
    }
}
