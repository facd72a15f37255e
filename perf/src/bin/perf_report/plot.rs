//! Trade plots (SVG, plotters): cost per simulated second against error,
//! both on log scales, one line per series, one marker per iteration count.
use std::error::Error;
use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::sweep::{Kind, Series};

/// Errors below this are drawn at it (log scales cannot show 0).
pub const ERROR_FLOOR: f64 = 1e-9;

const COLORS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(188, 189, 34),
    RGBColor(127, 127, 127),
    RGBColor(227, 119, 194),
];
const RAPIER: RGBColor = RGBColor(214, 39, 40);

/// Log-scale bounds around `values`, a little padded.
fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && *v > 0.0) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (ERROR_FLOOR, 1.0);
    }
    if hi / lo < 10.0 {
        let mid = (hi * lo).sqrt();
        return (mid / 4.0, mid * 4.0);
    }
    (lo / 1.5, hi * 1.5)
}

/// Draws error measure `measure` (index into each point's errors) of
/// `series` against cost to `path`.
pub fn trade(
    path: &Path,
    title: &str,
    y_label: &str,
    series: &[Series],
    measure: usize,
) -> Result<(), Box<dyn Error>> {
    let err = |e: &[f64]| e.get(measure).copied().unwrap_or(0.0).max(ERROR_FLOOR);
    let points = series.iter().flat_map(|s| &s.points);
    let (x0, x1) = bounds(points.clone().map(|p| p.cost_ms));
    let (y0, y1) = bounds(points.map(|p| err(&p.errors)));

    let root = SVGBackend::new(path, (760, 500)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(60)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("cost: ms of wall time per simulated second (log)")
        .y_desc(y_label)
        .x_labels(8)
        .y_labels(8)
        .x_label_formatter(&|v| crate::report::sig(*v))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .light_line_style(RGBColor(240, 240, 240))
        .label_style(("sans-serif", 12))
        .draw()?;
    let floored = series
        .iter()
        .flat_map(|s| &s.points)
        .any(|p| p.errors.get(measure).copied().unwrap_or(0.0) < ERROR_FLOOR);
    if floored {
        root.draw(&Text::new(
            format!(
                "errors below {ERROR_FLOOR:.0e} (e.g. exactly 0) are drawn at {ERROR_FLOOR:.0e}"
            ),
            (90, 484),
            ("sans-serif", 11).into_font().color(&BLACK.mix(0.6)),
        ))?;
    }

    let mut palette = COLORS.iter().cycle();
    for s in series {
        let color = match s.kind {
            Kind::Rapier => RAPIER,
            Kind::Tamias => *palette.next().unwrap_or(&BLACK),
        };
        let xy: Vec<(f64, f64)> = s
            .points
            .iter()
            .map(|p| (p.cost_ms, err(&p.errors)))
            .collect();
        let dashed = s.kind == Kind::Rapier;
        let style = color.stroke_width(if dashed { 3 } else { 2 });
        chart
            .draw_series(LineSeries::new(xy.clone(), style))?
            .label(s.label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], style));
        chart.draw_series(
            xy.iter()
                .map(|&(x, y)| Circle::new((x, y), 3, color.filled())),
        )?;
        // Iteration counts next to the markers of the 1/60 s series.
        if s.label.ends_with("1/60 s") {
            chart.draw_series(s.points.iter().map(|p| {
                Text::new(
                    format!("{}", p.config.iterations),
                    (p.cost_ms, err(&p.errors)),
                    ("sans-serif", 11).into_font().color(&color),
                )
            }))?;
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font(("sans-serif", 12))
        .draw()?;
    root.present()?;
    Ok(())
}

/// Ratio plot: Tamias2D time / Rapier time per scene as bars on a log₂
/// axis (ticks at powers of 2), the value written at the end of each bar.
pub fn ratios(path: &Path, rows: &[(String, f64)]) -> Result<(), Box<dyn Error>> {
    let (lo, hi) = bounds(rows.iter().map(|r| r.1));
    let (lo, hi) = (lo.min(0.8).log2().floor(), hi.max(1.25).log2().ceil() + 0.3);
    let n = rows.len().max(1);
    let root = SVGBackend::new(path, (760, 40 + 22 * n as u32 + 60)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Time per step, Tamias2D / Rapier (same run; < 1: Tamias2D faster)",
            ("sans-serif", 16),
        )
        .margin(12)
        .x_label_area_size(36)
        .y_label_area_size(150)
        .build_cartesian_2d(lo..hi, (0..n).into_segmented())?;
    // First scene at the top.
    let names: Vec<String> = rows.iter().rev().map(|r| r.0.clone()).collect();
    chart
        .configure_mesh()
        .disable_y_mesh()
        .y_labels(n + 1)
        .x_labels((hi - lo) as usize + 1)
        .light_line_style(RGBColor(240, 240, 240))
        .y_label_formatter(&|v| match v {
            SegmentValue::CenterOf(i) => names.get(*i).cloned().unwrap_or_default(),
            _ => String::new(),
        })
        .x_label_formatter(&|v| format!("{}", 2f64.powf(v.round())))
        .x_desc("ratio (log scale)")
        .label_style(("sans-serif", 12))
        .draw()?;
    chart.draw_series(LineSeries::new(
        vec![(0.0, SegmentValue::Exact(0)), (0.0, SegmentValue::Last)],
        BLACK.mix(0.5).stroke_width(1),
    ))?;
    for (i, r) in rows.iter().rev().enumerate() {
        let x = r.1.log2();
        chart.draw_series(std::iter::once(PathElement::new(
            vec![
                (lo, SegmentValue::CenterOf(i)),
                (x, SegmentValue::CenterOf(i)),
            ],
            COLORS[0].stroke_width(8),
        )))?;
        chart.draw_series(std::iter::once(Text::new(
            format!(" {:.2}", r.1),
            (x, SegmentValue::CenterOf(i)),
            ("sans-serif", 11)
                .into_font()
                .into_text_style(&root)
                .pos(Pos::new(HPos::Left, VPos::Center)),
        )))?;
    }
    root.present()?;
    Ok(())
}
