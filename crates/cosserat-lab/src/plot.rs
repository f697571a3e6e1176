//! Line plots written as SVG files (load–deflection curves, error against cost on log–log axes).
//!
//! plotters' SVG backend writes labels as `<text>` elements, so no font is needed at build or run time
//! (a bitmap backend would need system fonts to draw text).

use anyhow::{Result, anyhow};
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;
use std::path::Path;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    /// A polyline.
    Line,
    /// Markers only.
    Points,
    /// A polyline with markers.
    LinePoints,
}

/// One data series.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// `(x, y)` points in drawing order.
    pub points: Vec<(f64, f64)>,
    /// How it is drawn.
    pub mark: Mark,
    /// Index into the palette.
    pub color: usize,
}

/// A plot: title, axis labels, axes kind and series.
#[derive(Debug, Clone)]
pub struct Plot {
    /// Caption.
    pub title: String,
    /// x axis label.
    pub x_label: String,
    /// y axis label.
    pub y_label: String,
    /// Logarithmic x and y axes.
    pub log_log: bool,
    /// The series.
    pub series: Vec<Series>,
}

const PALETTE: [RGBColor; 11] = [
    RGBColor(0, 0, 0),
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(23, 190, 207),
    RGBColor(227, 119, 194),
    RGBColor(188, 189, 34),
    RGBColor(127, 127, 127),
];

fn range(values: impl Iterator<Item = f64>, log: bool) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && (!log || *v > 0.0))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    if !lo.is_finite() {
        return None;
    }
    Some(if log {
        let (a, b) = (lo.log10().floor(), hi.log10().ceil().max(lo.log10().floor() + 1.0));
        (10f64.powf(a), 10f64.powf(b))
    } else {
        let pad = 0.05 * (hi - lo).max(1e-12 * hi.abs().max(1.0));
        (lo - pad, hi + pad)
    })
}

impl Plot {
    /// Writes the plot as an SVG file of 760 × 500 pixels.
    ///
    /// # Errors
    /// A plot without finite (on log axes: positive) points, or a failed write.
    pub fn write_svg(&self, path: &Path) -> Result<()> {
        let log = self.log_log;
        let all = || self.series.iter().flat_map(|s| s.points.iter());
        let (x0, x1) =
            range(all().map(|p| p.0), log).ok_or_else(|| anyhow!("no points to plot in {}", path.display()))?;
        let (y0, y1) =
            range(all().map(|p| p.1), log).ok_or_else(|| anyhow!("no points to plot in {}", path.display()))?;
        let root = SVGBackend::new(path, (760, 500)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let builder = |root| {
            let mut b = ChartBuilder::on(root);
            b.caption(&self.title, ("sans-serif", 18))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(70);
            b
        };
        if log {
            let chart = builder(&root)
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                .map_err(|e| anyhow!("{e}"))?;
            self.draw(chart, log)?;
        } else {
            let chart = builder(&root).build_cartesian_2d(x0..x1, y0..y1).map_err(|e| anyhow!("{e}"))?;
            self.draw(chart, log)?;
        }
        root.present().map_err(|e| anyhow!("writing {}: {e}", path.display()))?;
        Ok(())
    }

    fn draw<'a, X, Y>(&self, mut chart: ChartContext<'a, SVGBackend<'a>, Cartesian2d<X, Y>>, log: bool) -> Result<()>
    where
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
        (X, Y): Sized,
        X: AsRangedCoord,
        Y: AsRangedCoord,
    {
        chart
            .configure_mesh()
            .x_desc(self.x_label.as_str())
            .y_desc(self.y_label.as_str())
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        for s in &self.series {
            let color = PALETTE[s.color % PALETTE.len()];
            let points: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|p| p.0.is_finite() && p.1.is_finite() && (!log || (p.0 > 0.0 && p.1 > 0.0)))
                .collect();
            if points.is_empty() {
                continue;
            }
            if matches!(s.mark, Mark::Line | Mark::LinePoints) {
                chart
                    .draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))
                    .map_err(|e| anyhow!("{e}"))?
                    .label(s.label.as_str())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
            }
            if matches!(s.mark, Mark::Points | Mark::LinePoints) {
                let drawn = chart
                    .draw_series(points.iter().map(|&p| Circle::new(p, 3, color.filled())))
                    .map_err(|e| anyhow!("{e}"))?;
                if s.mark == Mark::Points {
                    drawn
                        .label(s.label.as_str())
                        .legend(move |(x, y)| Circle::new((x + 10, y), 3, color.filled()));
                }
            }
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_linear_and_log_log_svg_files() {
        let dir = std::env::temp_dir().join(format!("xtask_plot_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for log_log in [false, true] {
            let plot = Plot {
                title: "test".into(),
                x_label: "x".into(),
                y_label: "y".into(),
                log_log,
                series: vec![Series {
                    label: "x²".into(),
                    points: (1..10).map(|i| (i as f64, (i * i) as f64)).collect(),
                    mark: Mark::LinePoints,
                    color: 1,
                }],
            };
            let path = dir.join(format!("p{log_log}.svg"));
            plot.write_svg(&path).unwrap();
            let text = std::fs::read_to_string(&path).unwrap();
            assert!(text.starts_with("<svg") && text.contains("<polyline") && text.contains("x²"));
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_plot_without_positive_points_on_log_axes_is_an_error() {
        let plot = Plot {
            title: "t".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            log_log: true,
            series: vec![Series {
                label: "s".into(),
                points: vec![(0.0, -1.0)],
                mark: Mark::Points,
                color: 0,
            }],
        };
        assert!(plot.write_svg(&std::env::temp_dir().join("never_written.svg")).is_err());
    }
}
