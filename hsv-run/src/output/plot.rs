//! PNG figures: line plots of time histories (the paper's figures) and contour maps of fields
//! over a surface, drawn with `plotters` in the bundled font.

use super::*;

/// One line of a plot.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub label: String,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
}

/// One panel of a figure: title, axis labels (with units) and its lines.
#[derive(Debug, Clone, PartialEq)]
pub struct LinePlot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
}

/// Font for plot text: DejaVu Sans from the system (Debian `fonts-dejavu-core`), registered once.
fn register_font() -> Result<()> {
    static REGISTERED: OnceLock<std::result::Result<(), String>> = OnceLock::new();
    let outcome = REGISTERED.get_or_init(|| {
        const CANDIDATES: [&str; 3] = [
            "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
            "/usr/share/fonts/TTF/DejaVuSans.ttf",
            "/usr/share/fonts/dejavu/DejaVuSans.ttf",
        ];
        let bytes = CANDIDATES
            .iter()
            .find_map(|p| fs::read(p).ok())
            .ok_or_else(|| {
                format!(
                    "no plot font found (looked for {}); install Debian's fonts-dejavu-core",
                    CANDIDATES.join(", ")
                )
            })?;
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
            .map_err(|_| "the DejaVu Sans font file could not be parsed".to_owned())
    });
    outcome.clone().map_err(anyhow::Error::msg)
}

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(23, 190, 207),
];

/// Dash pattern of a line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Dash {
    #[default]
    Solid,
    Dashed,
    Dotted,
    LongDashed,
}

impl Dash {
    /// The `k`-th pattern, cycling.
    pub fn nth(k: usize) -> Self {
        [Dash::Solid, Dash::Dashed, Dash::Dotted, Dash::LongDashed][k % 4]
    }

    /// (dash, gap) lengths in pixels; `None` for a solid line.
    fn pattern(self) -> Option<(u32, u32)> {
        match self {
            Dash::Solid => None,
            Dash::Dashed => Some((9, 5)),
            Dash::Dotted => Some((2, 4)),
            Dash::LongDashed => Some((18, 6)),
        }
    }
}

/// How one series is drawn: palette colour, dash pattern, and whether only its points are
/// marked (events such as engine choking) instead of joined by a line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LineStyle {
    pub colour: usize,
    pub dash: Dash,
    pub markers_only: bool,
}

/// A [`LinePlot`] with a style per series (series without one get [`default_styles`]).
#[derive(Debug, Clone, PartialEq)]
pub struct StyledPlot {
    pub plot: LinePlot,
    pub styles: Vec<LineStyle>,
}

/// Styles that tell models apart: series are grouped by the first word of their label (the
/// model, as in "pod max"); each group gets its own dash pattern and, within a group, the
/// colours run in order, so "full-order max" and "pod max" share a colour and differ in dash.
/// When every group has one series, colour and dash both change from series to series.
pub fn default_styles(plot: &LinePlot) -> Vec<LineStyle> {
    let group_of = |s: &Series| s.label.split_whitespace().next().unwrap_or("").to_owned();
    let mut groups: Vec<String> = Vec::new();
    let mut members: Vec<usize> = Vec::new();
    let mut styles = Vec::with_capacity(plot.series.len());
    for s in &plot.series {
        let g = group_of(s);
        let index = match groups.iter().position(|x| *x == g) {
            Some(i) => i,
            None => {
                groups.push(g);
                members.push(0);
                groups.len() - 1
            }
        };
        styles.push((index, members[index]));
        members[index] += 1;
    }
    let singletons = members.iter().all(|&m| m <= 1);
    styles
        .into_iter()
        .enumerate()
        .map(|(i, (group, within))| LineStyle {
            colour: if singletons { i } else { within },
            dash: Dash::nth(group),
            markers_only: false,
        })
        .collect()
}

/// Axis range covering every finite value, padded by 5 % (and made non-empty).
fn padded_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if !lo.is_finite() {
        return 0.0..1.0;
    }
    let span = hi - lo;
    let pad = if span > 0.0 {
        0.05 * span
    } else {
        0.05 * lo.abs().max(1.0)
    };
    (lo - pad)..(hi + pad)
}

/// Draws `plots` as a grid of `columns` panels into a PNG of `width` × `height` pixels, each
/// with its legend beside the axes (never over the data); styles from [`default_styles`].
pub fn write_line_plots_png(
    path: &Path,
    plots: &[LinePlot],
    columns: usize,
    size: (u32, u32),
) -> Result<()> {
    let styled: Vec<StyledPlot> = plots
        .iter()
        .map(|p| StyledPlot {
            styles: default_styles(p),
            plot: p.clone(),
        })
        .collect();
    write_styled_plots_png(path, &styled, columns, size)
}

/// Width in pixels of the legend column for `labels` (12 px text, a 28 px line sample).
fn legend_width(labels: &[&str], panel_width: u32) -> u32 {
    let longest = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0) as u32;
    if longest == 0 {
        return 0;
    }
    (longest * 7 + 48).min(panel_width * 2 / 5)
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// Draws one panel of a grid figure.
type DrawPanel<T> = fn(&Area<'_>, &T) -> std::result::Result<(), Box<dyn std::error::Error>>;

/// A short sample of `style` from `(x, y)`, `length` pixels long.
fn draw_sample(
    area: &Area<'_>,
    (x, y): (i32, i32),
    length: i32,
    style: LineStyle,
) -> Result<(), Box<dyn std::error::Error>> {
    let colour = PALETTE[style.colour % PALETTE.len()];
    if style.markers_only {
        area.draw(&Circle::new((x + length / 2, y), 4, colour.filled()))?;
        return Ok(());
    }
    match style.dash.pattern() {
        None => area.draw(&PathElement::new(
            vec![(x, y), (x + length, y)],
            colour.stroke_width(2),
        ))?,
        Some((on, off)) => {
            let mut start = 0;
            while start < length {
                let end = (start + on as i32).min(length);
                area.draw(&PathElement::new(
                    vec![(x + start, y), (x + end, y)],
                    colour.stroke_width(2),
                ))?;
                start = end + off as i32;
            }
        }
    }
    Ok(())
}

/// Draws one panel: title over the whole panel, axes on the left, legend in a column on the
/// right.
fn draw_panel(area: &Area<'_>, styled: &StyledPlot) -> Result<(), Box<dyn std::error::Error>> {
    let plot = &styled.plot;
    let area = area.titled(&plot.title, ("sans-serif", 16))?;
    let labels: Vec<&str> = plot
        .series
        .iter()
        .map(|s| s.label.as_str())
        .filter(|l| !l.is_empty())
        .collect();
    let (width, _) = area.dim_in_pixel();
    let legend = legend_width(&labels, width);
    let (chart_area, legend_area) = area.split_horizontally(width - legend);
    let x_range = padded_range(plot.series.iter().flat_map(|s| s.x.iter().copied()));
    let y_range = padded_range(plot.series.iter().flat_map(|s| s.y.iter().copied()));
    let mut chart = ChartBuilder::on(&chart_area)
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(64)
        .build_cartesian_2d(x_range, y_range)?;
    chart
        .configure_mesh()
        .x_desc(plot.x_label.as_str())
        .y_desc(plot.y_label.as_str())
        .label_style(("sans-serif", 12))
        .draw()?;
    let defaults = default_styles(plot);
    let style_of = |i: usize| styled.styles.get(i).copied().unwrap_or(defaults[i]);
    for (i, series) in plot.series.iter().enumerate() {
        let style = style_of(i);
        let colour = PALETTE[style.colour % PALETTE.len()];
        let points: Vec<(f64, f64)> = series
            .x
            .iter()
            .zip(&series.y)
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .map(|(&x, &y)| (x, y))
            .collect();
        if style.markers_only {
            chart.draw_series(
                points
                    .iter()
                    .map(|&p| Circle::new(p, 5, colour.stroke_width(2))),
            )?;
            continue;
        }
        match style.dash.pattern() {
            None => {
                chart.draw_series(LineSeries::new(points, colour.stroke_width(2)))?;
            }
            Some((on, off)) => {
                chart.draw_series(DashedLineSeries::new(
                    points,
                    on,
                    off,
                    colour.stroke_width(2),
                ))?;
            }
        }
    }
    if legend > 0 {
        let mut row = 0;
        for (i, series) in plot.series.iter().enumerate() {
            if series.label.is_empty() {
                continue;
            }
            let y = 20 + 18 * row;
            draw_sample(&legend_area, (6, y), 28, style_of(i))?;
            legend_area.draw(&Text::new(
                series.label.clone(),
                (40, y - 7),
                ("sans-serif", 12).into_font(),
            ))?;
            row += 1;
        }
    }
    Ok(())
}

/// [`write_line_plots_png`] with explicit styles.
pub fn write_styled_plots_png(
    path: &Path,
    plots: &[StyledPlot],
    columns: usize,
    (width, height): (u32, u32),
) -> Result<()> {
    if plots.is_empty() {
        bail!("{}: nothing to plot", path.display());
    }
    register_font()?;
    draw_grid_png(path, None, plots, columns, (width, height), draw_panel)
}

/// Draws `items` as a grid of `columns` panels (each by `draw`, under a figure `title` when
/// given) into a PNG of `width` × `height` pixels, drawn beside `path` and renamed into place
/// like every other file (a failed drawing leaves no partial file).
fn draw_grid_png<T>(
    path: &Path,
    title: Option<&str>,
    items: &[T],
    columns: usize,
    (width, height): (u32, u32),
    draw: DrawPanel<T>,
) -> Result<()> {
    let columns = columns.clamp(1, items.len());
    let rows = items.len().div_ceil(columns);
    let partial = partial_path(path);
    // The backend lives inside the closure: dropped before the rename (it writes on drop).
    let render = || -> std::result::Result<(), Box<dyn std::error::Error>> {
        let root = BitMapBackend::new(&partial, (width, height)).into_drawing_area();
        root.fill(&WHITE)?;
        let root = match title {
            Some(title) => root.titled(title, ("sans-serif", 20))?,
            None => root,
        };
        let areas = root.split_evenly((rows, columns));
        for (item, area) in items.iter().zip(areas.iter()) {
            draw(area, item)?;
        }
        root.present()?;
        Ok(())
    };
    let drawn = render().and_then(|()| Ok(fs::rename(&partial, path)?));
    if let Err(e) = drawn {
        let _ = fs::remove_file(&partial);
        bail!("cannot draw {}: {e}", path.display());
    }
    Ok(())
}

/// A scalar field on a planform for a contour map: polygon cells over vertices in the plane.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldMap {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    /// Vertex positions in the plot plane, m.
    pub vertices: Vec<(f64, f64)>,
    /// The field at each vertex.
    pub values: Vec<f64>,
    /// Each cell's vertex indices (a convex polygon: triangle or quad).
    pub cells: Vec<Vec<usize>>,
    /// What the colour bar measures.
    pub value_label: String,
}

/// Contour levels of a map.
const CONTOUR_BANDS: usize = 12;

/// Blue-white-red colour of `t` in [-1, 1].
fn diverging(t: f64) -> RGBColor {
    let t = t.clamp(-1.0, 1.0);
    let mix = |a: f64, b: f64, w: f64| (a + (b - a) * w).round() as u8;
    if t < 0.0 {
        let w = -t;
        RGBColor(
            mix(247.0, 33.0, w),
            mix(247.0, 102.0, w),
            mix(247.0, 172.0, w),
        )
    } else {
        RGBColor(
            mix(247.0, 178.0, t),
            mix(247.0, 24.0, t),
            mix(247.0, 43.0, t),
        )
    }
}

/// The band colour of `v` on a symmetric scale of half-width `peak`: values are quantized to
/// [`CONTOUR_BANDS`] bands so the fill reads as filled contours.
fn band_colour(v: f64, peak: f64) -> RGBColor {
    if peak <= 0.0 {
        return diverging(0.0);
    }
    let bands = CONTOUR_BANDS as f64;
    let u = ((v / peak + 1.0) * 0.5 * bands)
        .floor()
        .clamp(0.0, bands - 1.0);
    diverging((u + 0.5) / bands * 2.0 - 1.0)
}

/// Draws one map: each cell split into triangles, each triangle subdivided and filled by band,
/// with iso-lines at the band edges (linear on each triangle) and a colour bar.
fn draw_map(area: &Area<'_>, map: &FieldMap) -> Result<(), Box<dyn std::error::Error>> {
    let area = area.titled(&map.title, ("sans-serif", 15))?;
    let (width, _) = area.dim_in_pixel();
    let (chart_area, bar_area) = area.split_horizontally(width.saturating_sub(70));
    let peak = map
        .values
        .iter()
        .map(|v| v.abs())
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max);
    let x_range = padded_range(map.vertices.iter().map(|v| v.0));
    let y_range = padded_range(map.vertices.iter().map(|v| v.1));
    let mut chart = ChartBuilder::on(&chart_area)
        .margin(6)
        .x_label_area_size(32)
        .y_label_area_size(52)
        .build_cartesian_2d(x_range, y_range)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(map.x_label.as_str())
        .y_desc(map.y_label.as_str())
        .label_style(("sans-serif", 11))
        .draw()?;
    let triangles: Vec<[usize; 3]> = map
        .cells
        .iter()
        .filter(|c| c.len() >= 3)
        .flat_map(|c| (1..c.len() - 1).map(move |k| [c[0], c[k], c[k + 1]]))
        .collect();
    const SUB: usize = 6;
    for t in &triangles {
        let p = t.map(|i| (map.vertices[i], map.values[i]));
        // Barycentric subdivision into SUB² small triangles, each filled by its centroid value.
        let at = |a: f64, b: f64| {
            let c = 1.0 - a - b;
            (
                (
                    a * p[0].0.0 + b * p[1].0.0 + c * p[2].0.0,
                    a * p[0].0.1 + b * p[1].0.1 + c * p[2].0.1,
                ),
                a * p[0].1 + b * p[1].1 + c * p[2].1,
            )
        };
        let n = SUB as f64;
        for i in 0..SUB {
            for j in 0..SUB - i {
                let (a, b) = (i as f64 / n, j as f64 / n);
                let mut small = vec![[(a, b), (a + 1.0 / n, b), (a, b + 1.0 / n)]];
                if i + j + 1 < SUB {
                    small.push([
                        (a + 1.0 / n, b),
                        (a + 1.0 / n, b + 1.0 / n),
                        (a, b + 1.0 / n),
                    ]);
                }
                for corners in small {
                    let pts: Vec<((f64, f64), f64)> =
                        corners.iter().map(|&(a, b)| at(a, b)).collect();
                    let value = pts.iter().map(|p| p.1).sum::<f64>() / 3.0;
                    let colour = band_colour(value, peak);
                    chart.draw_series(std::iter::once(Polygon::new(
                        pts.iter().map(|p| p.0).collect::<Vec<_>>(),
                        colour.filled(),
                    )))?;
                }
            }
        }
    }
    // Iso-lines at the band edges: where each triangle's linear field crosses the level.
    if peak > 0.0 {
        for level in 1..CONTOUR_BANDS {
            let v = (level as f64 / CONTOUR_BANDS as f64 * 2.0 - 1.0) * peak;
            for t in &triangles {
                let p = t.map(|i| (map.vertices[i], map.values[i]));
                let mut crossings = Vec::new();
                for (a, b) in [(0, 1), (1, 2), (2, 0)] {
                    let (fa, fb) = (p[a].1 - v, p[b].1 - v);
                    if (fa < 0.0) != (fb < 0.0) {
                        let w = fa / (fa - fb);
                        crossings.push((
                            p[a].0.0 + w * (p[b].0.0 - p[a].0.0),
                            p[a].0.1 + w * (p[b].0.1 - p[a].0.1),
                        ));
                    }
                }
                if crossings.len() == 2 {
                    chart.draw_series(std::iter::once(PathElement::new(
                        crossings,
                        BLACK.mix(0.6).stroke_width(1),
                    )))?;
                }
            }
        }
    }
    // Colour bar from -peak (bottom) to +peak (top).
    let (_, bar_height) = bar_area.dim_in_pixel();
    let (top, bottom) = (20i32, bar_height as i32 - 40);
    let span = (bottom - top).max(1);
    for band in 0..CONTOUR_BANDS {
        let y0 = bottom - span * band as i32 / CONTOUR_BANDS as i32;
        let y1 = bottom - span * (band as i32 + 1) / CONTOUR_BANDS as i32;
        let colour = diverging((band as f64 + 0.5) / CONTOUR_BANDS as f64 * 2.0 - 1.0);
        bar_area.draw(&Rectangle::new([(8, y1), (24, y0)], colour.filled()))?;
    }
    let font = ("sans-serif", 11).into_font();
    bar_area.draw(&Text::new(
        format!("{:+.2}", peak),
        (27, top - 5),
        font.clone(),
    ))?;
    bar_area.draw(&Text::new(
        "0".to_owned(),
        (27, (top + bottom) / 2 - 5),
        font.clone(),
    ))?;
    bar_area.draw(&Text::new(
        format!("{:+.2}", -peak),
        (27, bottom - 5),
        font.clone(),
    ))?;
    bar_area.draw(&Text::new(map.value_label.clone(), (2, bottom + 12), font))?;
    Ok(())
}

/// Draws `maps` as a grid of `columns` contour maps under a figure `title` (what all maps
/// share: component, model, condition) into a PNG of `width` × `height` pixels.
pub fn write_field_maps_png(
    path: &Path,
    title: &str,
    maps: &[FieldMap],
    columns: usize,
    (width, height): (u32, u32),
) -> Result<()> {
    if maps.is_empty() {
        bail!("{}: nothing to plot", path.display());
    }
    for map in maps {
        if map.values.len() != map.vertices.len()
            || map.cells.iter().flatten().any(|&i| i >= map.vertices.len())
        {
            bail!(
                "{}: map `{}` has {} values for {} vertices or a cell beyond them",
                path.display(),
                map.title,
                map.values.len(),
                map.vertices.len()
            );
        }
    }
    register_font()?;
    draw_grid_png(path, Some(title), maps, columns, (width, height), draw_map)
}
