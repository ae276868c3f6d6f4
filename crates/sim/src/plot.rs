//! SVG plots of recorded device trends (plotters, SVG backend): word and
//! float devices share the upper chart, bit devices are drawn as stacked
//! logic traces below it. Long series are reduced to min/max per pixel
//! column, so peaks survive and the file stays small.

use plotters::prelude::*;

use crate::scenario::fmt::{fmt_num, Kind};
use crate::scenario::TraceData;

/// Plot size in pixels.
pub const WIDTH: u32 = 960;
pub const HEIGHT: u32 = 540;

/// Height of a bit lane (the trace is 1 high, the rest holds its label).
const LANE: f64 = 2.0;

/// Points kept per series (min and max of each bucket).
const MAX_POINTS: usize = 1600;

const COLORS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// Reduces a series to at most about `MAX_POINTS` points: min and max of each
/// bucket, in time order.
fn decimate(points: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    if points.len() <= MAX_POINTS {
        return points;
    }
    let buckets = MAX_POINTS / 2;
    let per = points.len().div_ceil(buckets);
    let mut out = Vec::with_capacity(2 * buckets + 2);
    for chunk in points.chunks(per) {
        let (mut lo, mut hi) = (chunk[0], chunk[0]);
        for p in chunk {
            if p.1 < lo.1 {
                lo = *p;
            }
            if p.1 > hi.1 {
                hi = *p;
            }
        }
        if lo.0 <= hi.0 {
            out.push(lo);
            out.push(hi);
        } else {
            out.push(hi);
            out.push(lo);
        }
    }
    out
}

/// A step-shaped series (values hold until the next sample).
fn steps(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(points.len() * 2);
    for (i, p) in points.iter().enumerate() {
        if i > 0 {
            out.push((p.0, points[i - 1].1));
        }
        out.push(*p);
    }
    out
}

fn err<E: std::fmt::Debug>(e: E) -> String {
    format!("plot: {e:?}")
}

/// Renders `devices` (names of traced columns) over time as SVG text.
pub fn render_svg(trace: &TraceData, devices: &[String], title: &str) -> Result<String, String> {
    let mut analog = Vec::new();
    let mut bits = Vec::new();
    for d in devices {
        let j = trace
            .column_of(d)
            .ok_or_else(|| format!("plot: `{d}` was not traced"))?;
        let pts: Vec<(f64, f64)> = trace.series(j).filter(|p| p.1.is_finite()).collect();
        if trace.devices[j].1 == Kind::Bit {
            bits.push((trace.devices[j].0.clone(), pts));
        } else {
            analog.push((trace.devices[j].0.clone(), decimate(pts)));
        }
    }
    if trace.is_empty() {
        return Err("plot: no samples".into());
    }
    let t0 = *trace.times_us.first().unwrap_or(&0) as f64 / 1e6;
    let t1 = (*trace.times_us.last().unwrap_or(&0) as f64 / 1e6).max(t0 + 1e-6);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = root.titled(title, ("sans-serif", 20)).map_err(err)?;
        let bit_h = if bits.is_empty() {
            0
        } else if analog.is_empty() {
            HEIGHT - 40
        } else {
            (45 + 40 * bits.len() as u32).min((HEIGHT - 40) / 2)
        };
        let (top, bottom) = root.split_vertically(HEIGHT - 40 - bit_h);
        let mut color = 0;
        if !analog.is_empty() {
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for (_, pts) in &analog {
                for p in pts {
                    lo = lo.min(p.1);
                    hi = hi.max(p.1);
                }
            }
            if !lo.is_finite() {
                (lo, hi) = (0.0, 1.0);
            }
            let pad = ((hi - lo) * 0.05).max(1e-6);
            let mut chart = ChartBuilder::on(&top)
                .margin(10)
                .x_label_area_size(if bits.is_empty() { 35 } else { 20 })
                .y_label_area_size(60)
                .build_cartesian_2d(t0..t1, (lo - pad)..(hi + pad))
                .map_err(err)?;
            let mut mesh = chart.configure_mesh();
            mesh.light_line_style(RGBColor(235, 235, 235))
                .x_label_formatter(&|x| fmt_num(*x))
                .y_label_formatter(&|y| fmt_num(*y));
            if bits.is_empty() {
                mesh.x_desc("time [s]");
            }
            mesh.draw().map_err(err)?;
            for (name, pts) in analog {
                let c = COLORS[color % COLORS.len()];
                color += 1;
                chart
                    .draw_series(LineSeries::new(pts, c.stroke_width(2)))
                    .map_err(err)?
                    .label(name)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                    });
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()
                .map_err(err)?;
        }
        if !bits.is_empty() {
            // One lane per bit, the first on top, each labelled above its trace
            // in the trace's colour.
            let nb = bits.len();
            let mut chart = ChartBuilder::on(&bottom)
                .margin(10)
                .x_label_area_size(35)
                .y_label_area_size(60)
                .build_cartesian_2d(t0..t1, -0.25..(LANE * nb as f64))
                .map_err(err)?;
            chart
                .configure_mesh()
                .light_line_style(RGBColor(235, 235, 235))
                .x_desc("time [s]")
                .x_label_formatter(&|x| fmt_num(*x))
                .y_labels(0)
                .draw()
                .map_err(err)?;
            for (i, (name, pts)) in bits.into_iter().enumerate() {
                let c = COLORS[color % COLORS.len()];
                color += 1;
                let base = LANE * (nb - 1 - i) as f64;
                let shifted: Vec<(f64, f64)> =
                    pts.iter().map(|p| (p.0, base + p.1.min(1.0))).collect();
                // Keep only the transitions (and the ends) before drawing steps.
                let edges: Vec<(f64, f64)> = shifted
                    .iter()
                    .enumerate()
                    .filter(|(k, p)| *k == 0 || *k + 1 == shifted.len() || p.1 != shifted[k - 1].1)
                    .map(|(_, p)| *p)
                    .collect();
                chart
                    .draw_series(LineSeries::new(steps(&edges), c.stroke_width(2)))
                    .map_err(err)?;
                chart
                    .draw_series(std::iter::once(Text::new(
                        name,
                        (t0 + (t1 - t0) * 0.003, base + LANE - 0.08),
                        ("sans-serif", 13).into_font().color(&c),
                    )))
                    .map_err(err)?;
            }
        }
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// Renders and writes an SVG file.
pub fn write_svg(
    path: &std::path::Path,
    trace: &TraceData,
    devices: &[String],
    title: &str,
) -> Result<(), String> {
    let svg = render_svg(trace, devices, title)?;
    std::fs::write(path, svg).map_err(|e| format!("cannot write {}: {e}", path.display()))
}
