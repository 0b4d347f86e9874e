//! `fmsvm plot`: the tool path as a picture. [`Recorder`] takes canonical operations and keeps the path
//! (rapids and feeds as polylines, arcs as arcs) thinned to what a picture can show; [`render`] draws
//! it in one view, to SVG or PNG, with the extents of the shown axes and a scale bar.
//!
//! Memory: a point closer to the last one kept than 1/4096 of the path's extent so far (on every axis)
//! is merged into it, and so is an arc that bulges less than that from its chord; points are kept as
//! `f32` offsets from the first point (12 bytes each).
//!
//! Text: an SVG names the monospace font (the viewer draws it); a PNG is lettered here with ab_glyph
//! from DejaVu Sans Mono embedded in the binary (the `dejavu` crate; the Bitstream Vera licence is in
//! `LICENSE-DejaVu`), so no system font is needed. plotters' own font features are off.
#![forbid(unsafe_code)]

use std::f64::consts::{FRAC_PI_8, PI};
use std::fmt;
use std::path::Path;
use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, GlyphId, PxScale, ScaleFont};
use fmsvm_canon::{Arc, Canon, Plane, Pose};
use fmsvm_driver::request::{Choice, Named};
use fmsvm_driver::run::{Render, RenderStart};
use fmsvm_emit::stats::{Bounds, MM_PER_INCH, arc_to_mm, to_mm};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

mod stock;

/// Cells across each axis's extent within which consecutive points are merged: finer than the pixels
/// of any picture up to 4096 pixels wide.
const CELLS: f64 = 4096.0;

/// The largest picture side, pixels.
pub const MAX_SIDE: u32 = 8192;

/// Which way the path is looked at.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum View {
    /// From +Z: X to the right, Y up.
    #[default]
    Xy,
    /// From −Y: X to the right, Z up.
    Xz,
    /// From +X: Y to the right, Z up.
    Yz,
    /// Isometric from X+ Y− Z+ (front right, above): X to the lower right, Y to the upper right, Z up.
    Iso,
    /// A lathe's: Z to the right, X (the radius) up.
    Zx,
}

impl Choice for View {
    const NAMES: &'static [Named<Self>] = &[
        Named::new(View::Xy, "xy", "From above: X right, Y up"),
        Named::new(View::Xz, "xz", "From the front: X right, Z up"),
        Named::new(View::Yz, "yz", "From the side: Y right, Z up"),
        Named::new(View::Iso, "iso", "Isometric, from the front right above"),
        Named::new(View::Zx, "zx", "A lathe's: Z right, X (radius) up"),
    ];
}

impl View {
    /// The picture-plane coordinates (right, up) of the point X Y Z.
    #[inline]
    fn project(self, p: [f64; 3]) -> [f64; 2] {
        match self {
            View::Xy => [p[0], p[1]],
            View::Xz => [p[0], p[2]],
            View::Yz => [p[1], p[2]],
            View::Zx => [p[2], p[0]],
            View::Iso => {
                let (r2, r6) = (std::f64::consts::SQRT_2, 6f64.sqrt());
                [(p[0] + p[1]) / r2, (p[1] - p[0] + 2.0 * p[2]) / r6]
            }
        }
    }

    /// The axis the view looks along (None: the isometric view, which sees every axis).
    fn normal(self) -> Option<usize> {
        match self {
            View::Xy => Some(2),
            View::Xz => Some(1),
            View::Yz => Some(0),
            View::Zx => Some(1),
            View::Iso => None,
        }
    }

    /// The axes whose extents the picture shows.
    fn axes(self) -> &'static [usize] {
        match self {
            View::Xy => &[0, 1],
            View::Xz => &[0, 2],
            View::Yz => &[1, 2],
            View::Zx => &[2, 0],
            View::Iso => &[0, 1, 2],
        }
    }

    /// The view's name in the picture.
    fn name(self) -> &'static str {
        match self {
            View::Xy => "XY",
            View::Xz => "XZ",
            View::Yz => "YZ",
            View::Zx => "ZX (Z right, X up; a lathe's X is the radius)",
            View::Iso => "isometric",
        }
    }
}

/// A picture's file format.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Format {
    /// Scalable vector graphics.
    Svg,
    /// A PNG image.
    Png,
}

impl Format {
    /// The format a file name asks for by its extension (`.svg`, `.png`, any case).
    pub fn of(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?;
        if ext.eq_ignore_ascii_case("svg") {
            Some(Format::Svg)
        } else if ext.eq_ignore_ascii_case("png") {
            Some(Format::Png)
        } else {
            None
        }
    }
}

/// Why a picture was not made.
#[derive(Debug)]
pub enum PlotError {
    /// The picture could not be drawn (a size out of range, a name without .svg or .png).
    Draw(String),
}

impl fmt::Display for PlotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PlotError::Draw(m) => write!(f, "{m}"),
        }
    }
}

/// An arc as recorded: offsets from the recorder's origin.
#[derive(Clone, Copy, Debug)]
struct ArcPiece {
    /// Start X Y Z.
    from: [f32; 3],
    /// Centre in the plane's coordinates.
    centre: [f32; 2],
    /// Swept angle, radians: positive counter-clockwise in the plane, negative clockwise.
    sweep: f32,
    /// Travel of the axis normal to the plane (a helix).
    rise: f32,
    plane: Plane,
    /// The tool (index into the tools seen, 0: none selected).
    tool: u16,
}

/// One piece of the path, in order.
#[derive(Clone, Copy, Debug)]
enum Piece {
    /// A polyline: the points from the previous line's end up to `end`, by `tool` (0: none).
    Line { rapid: bool, end: usize, tool: u16 },
    /// An arc.
    Arc(ArcPiece),
}

/// The path of a program, recorded from its canonical operations (X Y Z; the rotary axes are not
/// drawn).
#[derive(Debug, Default)]
pub struct Recorder {
    /// Where the tool is, mm.
    at: Pose,
    /// G20 in force.
    inch: bool,
    /// The units of the first move: the picture's.
    picture_inch: Option<bool>,
    /// The first point: points are kept as offsets from it.
    origin: [f64; 3],
    /// Every point of every move, mm (arcs by their true extremes).
    bounds: Bounds,
    points: Vec<[f32; 3]>,
    pieces: Vec<Piece>,
    /// The polyline being recorded: whether it is a rapid, and its tool.
    open: Option<(bool, u16)>,
    /// The axis of depth (Z on a mill, X on a lathe) and its least and greatest value on the feed
    /// moves, mm (the depth ramp's range).
    depth_x: bool,
    feed_z: Option<[f64; 2]>,
    /// The tools selected (T), in the order first seen; `tool` is the one in force (its index + 1,
    /// 0 before any).
    tools: Vec<f64>,
    tool: u16,
    /// The last point kept in it.
    kept: [f64; 3],
    /// The tool has moved since the last point kept.
    dirty: bool,
    /// The stock's box (`--stock`), its least and greatest X Y Z in the program's first units.
    stock: Option<[[f64; 3]; 2]>,
    /// Feed moves along one axis alone (a drilled hole, a plunge): the axis, the point (kept as an
    /// offset) and the tool; a view looking along that axis sees each as a point and marks it.
    plunges: Vec<(u8, [f32; 3], u16)>,
    /// The run's limits, a move a block: the points kept are bounded by them.
    budget: fmsvm_block::OutputBudget,
    /// The positions the output's dialect can write (alarm 0003 past them, as `run --resolve`).
    reach: fmsvm_emit::dialect::Reach,
}

impl Recorder {
    /// An empty path; the tool starts at the origin.
    #[cfg(test)]
    pub fn new() -> Recorder {
        Recorder::default()
    }

    /// An empty path with the stock's box to outline: its least and greatest X Y Z in the units
    /// of the program's first move (work coordinates of the output frame).
    pub fn with_stock(
        stock: Option<[[f64; 3]; 2]>,
        budget: fmsvm_block::OutputBudget,
        reach: fmsvm_emit::dialect::Reach,
    ) -> Recorder {
        Recorder {
            stock,
            budget,
            reach,
            ..Recorder::default()
        }
    }

    /// Depth is along X (a lathe's: the radius) rather than Z.
    pub fn depth_along_x(mut self) -> Recorder {
        self.depth_x = true;
        self
    }

    /// The axis of depth: X on a lathe, else Z.
    fn depth_axis(&self) -> usize {
        if self.depth_x { 0 } else { 2 }
    }

    /// The stock's box in mm, if one was given.
    fn stock_mm(&self) -> Option<[[f64; 3]; 2]> {
        let k = if self.picture_inch.unwrap_or(self.inch) {
            MM_PER_INCH
        } else {
            1.0
        };
        self.stock.map(|b| b.map(|p| p.map(|v| v * k)))
    }

    /// Places the tool at `at` (the units in force) without a move: where the program starts.
    pub fn start(&mut self, at: Pose) {
        self.close();
        self.at = to_mm(&at, self.inch);
    }

    /// Takes one operation.
    pub fn op(&mut self, op: &Canon<'_>) {
        match *op {
            Canon::Start(at) => self.start(at),
            Canon::Rapid(to) | Canon::Reference { to, .. } | Canon::Machine { to, .. } => {
                self.line(true, to_mm(&to, self.inch))
            }
            Canon::Thread { to, .. } => self.line(false, to_mm(&to, self.inch)),
            Canon::Feed(to) | Canon::Skip(to) => {
                let to = to_mm(&to, self.inch);
                self.plunge(&to);
                self.line(false, to)
            }
            Canon::Arc(arc) => self.arc(arc_to_mm(&arc, self.inch)),
            Canon::Units(inch) => self.inch = inch,
            Canon::Tool(t) => self.select_tool(t),
            _ => {}
        }
    }

    /// T: the moves that follow are this tool's (a picture has at most 65 535 tools apart).
    fn select_tool(&mut self, t: f64) {
        let i = match self.tools.iter().position(|&k| k == t) {
            Some(i) => i,
            None if self.tools.len() < usize::from(u16::MAX - 1) => {
                self.tools.push(t);
                self.tools.len() - 1
            }
            None => return,
        };
        self.tool = i as u16 + 1;
    }

    /// Points kept (for tests of the thinning).
    #[cfg(test)]
    fn kept_points(&self) -> usize {
        self.points.len()
    }

    /// The box of everything recorded, mm; `None` before any move.
    pub fn bounds(&self) -> Option<Bounds> {
        (!self.bounds.is_empty()).then_some(self.bounds)
    }

    /// Before a move: the picture's units and the origin are set by the first.
    fn begin(&mut self) {
        if self.picture_inch.is_none() {
            self.picture_inch = Some(self.inch);
            self.origin = xyz(&self.at);
        }
    }

    /// `p` as kept: the offset from the origin.
    fn offset(&self, p: [f64; 3]) -> [f32; 3] {
        [
            (p[0] - self.origin[0]) as f32,
            (p[1] - self.origin[1]) as f32,
            (p[2] - self.origin[2]) as f32,
        ]
    }

    /// Whether `a` and `b` are further apart than a cell on some axis.
    fn apart(&self, a: [f64; 3], b: [f64; 3]) -> bool {
        (0..3).any(|i| (a[i] - b[i]).abs() > (self.bounds.max[i] - self.bounds.min[i]) / CELLS)
    }

    fn line(&mut self, rapid: bool, to: Pose) {
        // A move from or to a place not known (an axis the program has not positioned, a
        // reference position --offsets does not give) cannot be drawn: the path resumes at its end.
        if xyz(&self.at).iter().chain(&xyz(&to)).any(|v| v.is_nan()) {
            self.close();
            self.at = to;
            return;
        }
        self.begin();
        self.bounds.add(&self.at);
        self.bounds.add(&to);
        if !rapid {
            self.feed_depth(self.at[self.depth_axis()]);
            self.feed_depth(to[self.depth_axis()]);
        }
        if self.open != Some((rapid, self.tool)) {
            self.close();
            let from = xyz(&self.at);
            self.points.push(self.offset(from));
            self.kept = from;
            self.open = Some((rapid, self.tool));
        }
        let end = xyz(&to);
        if self.apart(self.kept, end) {
            self.points.push(self.offset(end));
            self.kept = end;
            self.dirty = false;
        } else {
            self.dirty = true;
        }
        self.at = to;
    }

    /// Notes a feed move from the tool's position to `to` along one axis alone (its other two
    /// unchanged): one mark a place, however many pecks reach it.
    fn plunge(&mut self, to: &Pose) {
        let (from, end) = (xyz(&self.at), xyz(to));
        if from.iter().chain(&end).any(|v| v.is_nan()) {
            return;
        }
        let moved: Vec<usize> = (0..3)
            .filter(|&i| (end[i] - from[i]).abs() > 1e-9)
            .collect();
        let [axis] = moved[..] else {
            return;
        };
        self.begin();
        let at = self.offset(end);
        let same_place = |p: &[f32; 3]| (0..3).all(|i| i == axis || (p[i] - at[i]).abs() < 1e-4);
        if let Some((a, last, _)) = self.plunges.last()
            && usize::from(*a) == axis
            && same_place(last)
        {
            return;
        }
        self.plunges.push((axis as u8, at, self.tool));
    }

    /// Ends the polyline being recorded, with the tool's position as its last point.
    fn close(&mut self) {
        if let Some((rapid, tool)) = self.open.take() {
            if self.dirty {
                let at = self.offset(xyz(&self.at));
                self.points.push(at);
                self.dirty = false;
            }
            self.pieces.push(Piece::Line {
                rapid,
                end: self.points.len(),
                tool,
            });
        }
    }

    /// A feed move reaches depth `z`.
    fn feed_depth(&mut self, z: f64) {
        let [lo, hi] = self.feed_z.get_or_insert([z, z]);
        *lo = lo.min(z);
        *hi = hi.max(z);
    }

    fn arc(&mut self, arc: Arc) {
        self.begin();
        let from = self.at;
        self.feed_depth(from[self.depth_axis()]);
        self.feed_depth(arc.to[self.depth_axis()]);
        self.bounds.add_arc(&from, &arc);
        let (r, sweep) = arc.sweep(&from);
        let (a, b, n) = arc.plane.axes();
        let cell = (self.bounds.max[a] - self.bounds.min[a])
            .min(self.bounds.max[b] - self.bounds.min[b])
            / CELLS;
        // How far the arc leaves its chord: an arc that stays within a cell is a line.
        let bulge = if sweep >= PI {
            r
        } else {
            r * (1.0 - (sweep / 2.0).cos())
        };
        if !bulge.is_finite() || bulge <= cell {
            self.line(false, arc.to);
            return;
        }
        self.close();
        let o = self.origin;
        self.pieces.push(Piece::Arc(ArcPiece {
            from: self.offset(xyz(&from)),
            centre: [(arc.centre[0] - o[a]) as f32, (arc.centre[1] - o[b]) as f32],
            sweep: if arc.clockwise { -sweep } else { sweep } as f32,
            rise: (arc.to[n] - from[n]) as f32,
            plane: arc.plane,
            tool: self.tool,
        }));
        self.at = arc.to;
    }

    /// The pieces with the points of each polyline, in order.
    fn walk(&self, mut f: impl FnMut(Drawn<'_>)) {
        let mut start = 0;
        for piece in &self.pieces {
            match *piece {
                Piece::Line { rapid, end, tool } => {
                    f(Drawn::Line(rapid, &self.points[start..end], None, tool));
                    start = end;
                }
                Piece::Arc(a) => f(Drawn::Arc(a)),
            }
        }
        if let Some((rapid, tool)) = self.open {
            let last = self.dirty.then(|| self.offset(xyz(&self.at)));
            f(Drawn::Line(rapid, &self.points[start..], last, tool));
        }
    }
}

/// A piece as [`Recorder::walk`] gives it.
enum Drawn<'a> {
    /// A rapid or not, its points, a last point not kept yet (the polyline being recorded), and
    /// its tool.
    Line(bool, &'a [[f32; 3]], Option<[f32; 3]>, u16),
    Arc(ArcPiece),
}

fn xyz(p: &Pose) -> [f64; 3] {
    [p[0], p[1], p[2]]
}

/// Draws `path` in `view` to `out` (SVG or PNG by its extension), `size` = (width, height) in pixels
/// (the tests' way in; `fmsvm plot` writes `picture` through its planned output).
#[cfg(test)]
pub fn render(
    path: &Recorder,
    out: &Path,
    view: View,
    colour: Colour,
    size: (u32, u32),
) -> Result<(), PlotError> {
    let format = Format::of(out).ok_or_else(|| {
        PlotError::Draw(format!(
            "{}: the picture's name must end in .svg or .png",
            out.display()
        ))
    })?;
    let bytes = picture(path, format, view, colour, size)?;
    std::fs::write(out, bytes).map_err(|e| PlotError::Draw(e.to_string()))
}

/// The bytes of the picture of `path` in `view`, its feed moves coloured by `colour`: an SVG
/// document (its coordinates in tenths of a pixel) or a PNG file.
pub fn picture(
    path: &Recorder,
    format: Format,
    view: View,
    colour: Colour,
    size: (u32, u32),
) -> Result<Vec<u8>, PlotError> {
    check_size(size)?;
    let (w, h) = size;
    match format {
        Format::Svg => {
            let unit = SVG_UNIT as u32;
            let mut text = String::new();
            {
                let root =
                    SVGBackend::with_string(&mut text, (w * unit, h * unit)).into_drawing_area();
                let labels = draw(&root, path, view, colour, SVG_UNIT).map_err(drawing)?;
                let style = TextStyle::from(
                    (FontFamily::Monospace, TEXT_SIZE * f64::from(SVG_UNIT)).into_font(),
                )
                .pos(Pos::new(HPos::Left, VPos::Top))
                .color(&BLACK);
                for l in &labels {
                    root.draw_text(&l.text, &style, (l.x, l.y))
                        .map_err(drawing)?;
                }
                root.present().map_err(drawing)?;
            }
            // The document is W×H pixels; its coordinates are tenths of one (the viewBox).
            let head = format!("width=\"{}\" height=\"{}\"", w * unit, h * unit);
            let Some(at) = text.find(&head) else {
                return Err(PlotError::Draw(
                    "the SVG's header is not as plotters writes it".into(),
                ));
            };
            text.replace_range(
                at..at + head.len(),
                &format!("width=\"{w}\" height=\"{h}\""),
            );
            Ok(text.into_bytes())
        }
        Format::Png => {
            let font = font()?;
            let mut pixels = vec![0u8; w as usize * h as usize * 3];
            let labels = {
                let root = BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area();
                let labels = draw(&root, path, view, colour, 1).map_err(drawing)?;
                root.present().map_err(drawing)?;
                labels
            };
            for l in &labels {
                lettering(&mut pixels, size, font, l);
            }
            png_bytes(&pixels, size)
        }
    }
}

/// A picture's side is 1 to `MAX_SIDE` pixels.
fn check_size((w, h): (u32, u32)) -> Result<(), PlotError> {
    if (1..=MAX_SIDE).contains(&w) && (1..=MAX_SIDE).contains(&h) {
        return Ok(());
    }
    Err(PlotError::Draw(format!(
        "a picture of {w}x{h} pixels: each side must be 1 to {MAX_SIDE}"
    )))
}

/// RGB pixels of `size` as a PNG file.
fn png_bytes(px: &[u8], (w, h): (u32, u32)) -> Result<Vec<u8>, PlotError> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder
        .write_header()
        .and_then(|mut wr| wr.write_image_data(px))
        .map_err(|e| PlotError::Draw(format!("encoding the PNG: {e}")))?;
    Ok(bytes)
}

/// RGB pixels as the picture's file: a PNG, or an SVG of rectangles (runs of one colour along a
/// row of blocks at most 300 across, so the document stays a few megabytes).
fn encode(px: &[u8], (w, h): (u32, u32), format: Format) -> Result<Vec<u8>, PlotError> {
    match format {
        Format::Png => png_bytes(px, (w, h)),
        Format::Svg => {
            use std::fmt::Write;
            let block = w.max(h).div_ceil(300).max(1);
            let mut s = format!(
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" shape-rendering=\"crispEdges\">\n"
            );
            let colour = |x: u32, y: u32| {
                let k = (y as usize * w as usize + x as usize) * 3;
                [px[k], px[k + 1], px[k + 2]]
            };
            for y in (0..h).step_by(block as usize) {
                let mut x = 0;
                while x < w {
                    let c = colour(x, y);
                    let mut end = x + block;
                    while end < w && colour(end, y) == c {
                        end += block;
                    }
                    let end = end.min(w);
                    if c != [255, 255, 255] {
                        let _ = writeln!(
                            s,
                            "<rect x=\"{x}\" y=\"{y}\" width=\"{}\" height=\"{}\" fill=\"#{:02x}{:02x}{:02x}\"/>",
                            end - x,
                            block.min(h - y),
                            c[0],
                            c[1],
                            c[2]
                        );
                    }
                    x = end;
                }
            }
            s.push_str("</svg>\n");
            Ok(s.into_bytes())
        }
    }
}

fn drawing(e: impl fmt::Display) -> PlotError {
    PlotError::Draw(format!("drawing the picture: {e}"))
}

/// The embedded font (DejaVu Sans Mono), parsed once.
fn font() -> Result<&'static FontRef<'static>, PlotError> {
    static FONT: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(dejavu::sans_mono::regular()).ok())
        .as_ref()
        .ok_or_else(|| PlotError::Draw("the embedded font does not load".into()))
}

/// A line of text on the picture.
#[derive(Clone, Debug)]
struct Label {
    text: String,
    /// The left end, pixels.
    x: i32,
    /// The top of the text, pixels.
    y: i32,
}

impl Label {
    fn left(text: String, x: i32, y: i32) -> Label {
        Label { text, x, y }
    }
}

/// Letters `label` into an RGB picture, black, anti-aliased (the PNG's text; an SVG names a font).
fn lettering(pixels: &mut [u8], (w, h): (u32, u32), font: &FontRef<'_>, label: &Label) {
    // The SVG's font size is TEXT_SIZE / 1.24 per em (plotters' rule); the same em here.
    let em = (TEXT_SIZE / 1.24) as f32;
    let scale = PxScale::from(em * font.height_unscaled() / font.units_per_em().unwrap_or(2048.0));
    let scaled = font.as_scaled(scale);
    let glyphs: Vec<GlyphId> = label.text.chars().map(|c| scaled.glyph_id(c)).collect();
    let mut x = label.x as f32;
    let baseline = label.y as f32 + 0.76 * em;
    for g in glyphs {
        let glyph = g.with_scale_and_position(scale, ab_glyph::point(x, baseline));
        x += scaled.h_advance(g);
        let Some(outline) = font.outline_glyph(glyph) else {
            continue;
        };
        let b = outline.px_bounds();
        outline.draw(|gx, gy, coverage| {
            let (px, py) = (b.min.x as i64 + gx as i64, b.min.y as i64 + gy as i64);
            if px < 0 || py < 0 || px >= w as i64 || py >= h as i64 {
                return;
            }
            let i = (py as usize * w as usize + px as usize) * 3;
            let keep = 1.0 - coverage.clamp(0.0, 1.0);
            for v in &mut pixels[i..i + 3] {
                *v = (*v as f32 * keep).round() as u8;
            }
        });
    }
}

/// How the feed moves are coloured.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum Colour {
    /// By depth: Z along a ramp from deep (dark) to high (light), the range in the legend; what
    /// shows the shape of a raster from above.
    #[default]
    Depth,
    /// By tool (T): a colour each, named in the legend.
    Tool,
    /// One colour for every feed move.
    Motion,
}

impl Choice for Colour {
    const NAMES: &'static [Named<Self>] = &[
        Named::new(Colour::Depth, "depth", "By depth (Z)"),
        Named::new(Colour::Tool, "tool", "By tool (T)"),
        Named::new(Colour::Motion, "motion", "One colour"),
    ];
}

/// `fmsvm plot`'s consumer of a run: the path recorded as the run goes, then drawn.
pub struct Picture {
    recorder: Recorder,
    format: Format,
    /// None: the machine's (XY for a mill, ZX for a lathe).
    view: Option<View>,
    colour: Colour,
    size: (u32, u32),
    lathe: bool,
    /// With `--stock`: the part as the program left it, drawn instead of the path.
    stock: Option<(fmsvm_stock::Stock, fmsvm_stock::Report)>,
}

impl Picture {
    /// A picture to draw in `format`, `size` pixels.
    pub fn new(format: Format, view: Option<View>, colour: Colour, size: (u32, u32)) -> Picture {
        Picture {
            recorder: Recorder::default(),
            format,
            view,
            colour,
            size,
            lathe: false,
            stock: None,
        }
    }
}

impl Render for Picture {
    fn start(&mut self, run: RenderStart) {
        self.recorder = Recorder::with_stock(run.stock, run.budget, run.reach);
        if run.lathe {
            self.recorder = std::mem::take(&mut self.recorder).depth_along_x();
        }
        self.lathe = run.lathe;
    }

    fn canon(
        &mut self,
        op: &Canon<'_>,
        origin: fmsvm_canon::Origin,
    ) -> Result<(), fmsvm_block::Stop> {
        fmsvm_canon::Emitter::canon(&mut self.recorder, op, origin)
    }

    /// The part is drawn when a tool with a shape cut (or could have cut) the stock; otherwise
    /// the path, with the stock's outline.
    fn stock(&mut self, stock: fmsvm_stock::Stock, report: fmsvm_stock::Report) {
        if !report.tools.is_empty() {
            self.stock = Some((stock, report));
        }
    }

    fn render(&mut self) -> Result<Vec<u8>, String> {
        if let Some((stock, report)) = &self.stock {
            let px = stock::pixels(stock, report, self.size).map_err(|e| e.to_string())?;
            return encode(&px, self.size, self.format).map_err(|e| e.to_string());
        }
        let view = self
            .view
            .unwrap_or(if self.lathe { View::Zx } else { View::Xy });
        picture(&self.recorder, self.format, view, self.colour, self.size)
            .map_err(|e| e.to_string())
    }
}

/// Text: the size, the lines' spacing and the monospace advance (DejaVu Sans Mono, 0.602 em; the
/// em is the size / 1.24, plotters' rule), pixels.
const TEXT_SIZE: f64 = 18.0;
const LINE: i32 = 20;
const ADVANCE: f64 = TEXT_SIZE / 1.24 * 0.602;
/// The margin at the sides and above the header, pixels.
const SIDE: i32 = 16;
/// SVG coordinates are in tenths of a pixel (the viewBox says so): a path keeps its sub-pixel
/// detail where a PNG's pixels cannot.
const SVG_UNIT: i32 = 10;

const FEED: RGBColor = RGBColor(0, 84, 190);
const RAPID: RGBColor = RGBColor(214, 64, 0);
const STOCK: RGBColor = RGBColor(150, 150, 150);
/// The depth ramp (viridis's stops), deep to high, in `BUCKETS` steps.
const RAMP: [RGBColor; 5] = [
    RGBColor(68, 1, 84),
    RGBColor(59, 82, 139),
    RGBColor(33, 145, 140),
    RGBColor(94, 201, 98),
    RGBColor(253, 231, 37),
];
const BUCKETS: usize = 32;
/// The tools' colours, in the order the tools are first selected (then again).
const TOOLS: [RGBColor; 8] = [
    RGBColor(0, 84, 190),
    RGBColor(0, 140, 70),
    RGBColor(140, 60, 170),
    RGBColor(150, 90, 40),
    RGBColor(200, 40, 120),
    RGBColor(0, 150, 170),
    RGBColor(90, 90, 90),
    RGBColor(120, 120, 0),
];

/// The ramp's colour at `t` (0 deep … 1 high).
fn ramp(t: f64) -> RGBColor {
    let x = t.clamp(0.0, 1.0) * (RAMP.len() - 1) as f64;
    let k = (x.floor() as usize).min(RAMP.len() - 2);
    let f = x - k as f64;
    let mix = |a: u8, b: u8| (f64::from(a) + (f64::from(b) - f64::from(a)) * f).round() as u8;
    let (a, b) = (RAMP[k], RAMP[k + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// How a picture colours its feed moves: the mode with the depth range (mm).
#[derive(Clone, Copy, Debug)]
struct Paint {
    colour: Colour,
    z: [f64; 2],
}

impl Paint {
    /// The bucket of a feed move at depth `z` by `tool` (its colour's index).
    fn bucket(&self, z: f64, tool: u16) -> usize {
        match self.colour {
            Colour::Depth => {
                let span = self.z[1] - self.z[0];
                let t = if span > 0.0 {
                    (z - self.z[0]) / span
                } else {
                    1.0
                };
                (t.clamp(0.0, 1.0) * (BUCKETS - 1) as f64).round() as usize
            }
            Colour::Tool => usize::from(tool.saturating_sub(1)) % TOOLS.len(),
            Colour::Motion => 0,
        }
    }

    fn colour(&self, bucket: usize) -> RGBColor {
        match self.colour {
            Colour::Depth => ramp(bucket as f64 / (BUCKETS - 1) as f64),
            Colour::Tool => TOOLS[bucket % TOOLS.len()],
            Colour::Motion => FEED,
        }
    }
}

/// Where the picture plane goes in pixels: `scale` pixels per mm about a centre.
#[derive(Clone, Copy, Debug)]
struct Frame {
    view: View,
    origin: [f64; 3],
    scale: f64,
    centre: [f64; 2],
    pixel_centre: [f64; 2],
}

impl Frame {
    /// The frame that fits the path into the drawing box (left, right, top, bottom).
    fn fit(
        view: View,
        path: &Recorder,
        bounds: &Bounds,
        (x0, x1, y0, y1): (i32, i32, i32, i32),
    ) -> Frame {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        let mut add = |q: [f64; 2]| {
            for k in 0..2 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        };
        if view == View::Iso {
            // The box's corners are not on the path: walk it (arcs at 64 points a turn).
            let o = path.origin;
            let at = |p: [f64; 3]| [0, 1, 2].map(|i| o[i] + p[i]);
            path.walk(|piece| match piece {
                Drawn::Line(_, points, last, _) => {
                    for p in points.iter().chain(&last) {
                        add(view.project(at(p.map(f64::from))));
                    }
                }
                Drawn::Arc(a) => {
                    let steps = (f64::from(a.sweep).abs() / (PI / 32.0)).ceil() as usize;
                    arc_points(&a, steps, |p| add(view.project(at(p))));
                }
            });
        } else {
            for corner in [bounds.min, bounds.max] {
                add(view.project(xyz(&corner)));
            }
        }
        for corner in path.stock_mm().iter().flat_map(box_corners) {
            add(view.project(corner));
        }
        let (bw, bh) = ((x1 - x0) as f64, (y1 - y0) as f64);
        let (ew, eh) = (hi[0] - lo[0], hi[1] - lo[1]);
        let scale = match (ew > 0.0, eh > 0.0) {
            (true, true) => (bw / ew).min(bh / eh),
            (true, false) => bw / ew,
            (false, true) => bh / eh,
            (false, false) => 1.0,
        };
        Frame {
            view,
            origin: path.origin,
            scale,
            centre: [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0],
            pixel_centre: [(x0 + x1) as f64 / 2.0, (y0 + y1) as f64 / 2.0],
        }
    }

    /// The pixel of the point X Y Z (mm).
    #[inline]
    fn pixel(&self, p: [f64; 3]) -> (i32, i32) {
        let [u, v] = self.view.project(p);
        (
            (self.pixel_centre[0] + (u - self.centre[0]) * self.scale).round() as i32,
            (self.pixel_centre[1] - (v - self.centre[1]) * self.scale).round() as i32,
        )
    }

    /// The pixel of a recorded offset.
    #[inline]
    fn pixel_of(&self, p: [f64; 3]) -> (i32, i32) {
        self.pixel([0, 1, 2].map(|i| self.origin[i] + p[i]))
    }
}

/// `text` in lines of at most `width` pixels, broken at spaces (a word longer stays whole).
fn wrap(text: &str, width: i32) -> Vec<String> {
    let fits = |t: &str| t.chars().count() as f64 * ADVANCE <= f64::from(width);
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ') {
        match lines.last_mut() {
            Some(l) if fits(&format!("{l} {word}")) => {
                l.push(' ');
                l.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

/// The width of `text` in pixels.
fn text_width(text: &str) -> i32 {
    (text.chars().count() as f64 * ADVANCE).ceil() as i32
}

/// One item of the legend: its swatch and its name.
#[derive(Clone, Debug)]
enum Swatch {
    /// A solid line of a colour.
    Solid(RGBColor),
    /// A dashed line of a colour.
    Dashed(RGBColor),
    /// The depth ramp, deep to high.
    Ramp,
}

/// The swatch's width and the gap after an item, pixels.
const SWATCH: i32 = 30;
const RAMP_SWATCH: i32 = 48;
const GAP: i32 = 14;

fn item_width((swatch, name): &(Swatch, String)) -> i32 {
    let w = if matches!(swatch, Swatch::Ramp) {
        RAMP_SWATCH
    } else {
        SWATCH
    };
    w + 6 + text_width(name) + GAP
}

/// Draws the path, the scale bar and the legend's lines; gives the text to letter (positions in
/// the backend's units, `unit` a pixel).
fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    path: &Recorder,
    view: View,
    colour: Colour,
    unit: i32,
) -> Result<Vec<Label>, DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let (bw, bh) = root.dim_in_pixel();
    let (w, h) = (bw as i32 / unit, bh as i32 / unit);
    let u = |v: i32| v * unit;
    let inch = path.picture_inch.unwrap_or(path.inch);
    let (units, k, digits) = if inch {
        ("in", 1.0 / MM_PER_INCH, 4)
    } else {
        ("mm", 1.0, 3)
    };
    let Some(bounds) = path.bounds() else {
        let text = format!("{} view: no motion", view.name());
        return Ok(vec![Label::left(text, u(SIDE), u(6))]);
    };
    let room = w - 2 * SIDE;
    // The header: the view, then the extents of its axes on one line or one an axis.
    let names = fmsvm_canon::AXES.map(|l| l.as_str());
    let extents: Vec<String> = view
        .axes()
        .iter()
        .map(|&i| {
            if bounds.min[i] > bounds.max[i] {
                format!("{} not positioned", names[i])
            } else {
                format!(
                    "{} {:.digits$} .. {:.digits$}",
                    names[i],
                    bounds.min[i] * k,
                    bounds.max[i] * k
                )
            }
        })
        .collect();
    let mut header = wrap(&format!("{} view, {units}", view.name()), room);
    let joined = extents.join("   ");
    if text_width(&joined) <= room {
        header.push(joined);
    } else {
        header.extend(extents);
    }
    let top = 6 + header.len() as i32 * LINE + 6;
    // The legend: the feed moves' colours, a dashed rapid, the stock.
    let d = path.depth_axis();
    let depth = path.feed_z.unwrap_or([bounds.min[d], bounds.max[d]]);
    let paint = Paint { colour, z: depth };
    let mut legend: Vec<(Swatch, String)> = Vec::new();
    match colour {
        Colour::Depth => legend.push((
            Swatch::Ramp,
            format!(
                "feed {} {:.digits$} .. {:.digits$}",
                names[d],
                depth[0] * k,
                depth[1] * k
            ),
        )),
        Colour::Tool if !path.tools.is_empty() => {
            for (i, t) in path.tools.iter().enumerate().take(TOOLS.len()) {
                legend.push((Swatch::Solid(TOOLS[i]), format!("T{}", trim(*t))));
            }
            if path.tools.len() > TOOLS.len() {
                legend.push((
                    Swatch::Solid(TOOLS[0]),
                    format!("… {} tools, colours repeat", path.tools.len()),
                ));
            }
        }
        Colour::Tool | Colour::Motion => legend.push((Swatch::Solid(FEED), "feed".into())),
    }
    legend.push((Swatch::Dashed(RAPID), "rapid".into()));
    if path.stock.is_some() {
        legend.push((Swatch::Solid(STOCK), "stock".into()));
    }
    // The footer: the scale bar (at most a fifth of the width and its label) and the legend on
    // one row when they fit side by side, else the legend in rows of its own above the bar.
    let bar_room = room / 5 + 8 + text_width("0.0005 mm (picture plane)");
    let legend_width: i32 = legend.iter().map(item_width).sum::<i32>() - GAP;
    let mut rows: Vec<Vec<(Swatch, String)>> = vec![Vec::new()];
    let side_by_side = bar_room + GAP + legend_width <= room;
    for item in legend {
        let row = rows.last_mut().expect("a row");
        let used: i32 = row.iter().map(item_width).sum();
        if !side_by_side && !row.is_empty() && used + item_width(&item) - GAP > room {
            rows.push(vec![item]);
        } else {
            row.push(item);
        }
    }
    let footer_rows = rows.len() as i32 + i32::from(!side_by_side);
    let bottom = 44 + (footer_rows - 1) * LINE;
    let (x0, x1) = (SIDE.min(w / 4), (w - SIDE).max(SIDE.min(w / 4) + 1));
    let (y0, y1) = (top.min(h / 3), (h - bottom).max(top.min(h / 3) + 1));
    let frame = Frame::fit(view, path, &bounds, (u(x0), u(x1), u(y0), u(y1)));
    let stock = ShapeStyle::from(&STOCK).stroke_width(u(1) as u32);
    if let Some(b) = path.stock_mm() {
        // The box's twelve edges: its outline in every view (the near edges cover the far ones).
        let c = box_corners(&b);
        for (i, j) in [
            (0, 1),
            (2, 3),
            (4, 5),
            (6, 7),
            (0, 2),
            (1, 3),
            (4, 6),
            (5, 7),
            (0, 4),
            (1, 5),
            (2, 6),
            (3, 7),
        ] {
            root.draw(&PathElement::new(
                vec![frame.pixel(c[i]), frame.pixel(c[j])],
                stock,
            ))?;
        }
    }
    let rapid = ShapeStyle::from(&RAPID).stroke_width(u(1) as u32);
    let stroke = |bucket: usize| ShapeStyle::from(&paint.colour(bucket)).stroke_width(u(1) as u32);
    // The points of a piece with their Z; then drawn in runs of one colour.
    let mut points: Vec<((i32, i32), f64)> = Vec::new();
    let mut run: Vec<(i32, i32)> = Vec::new();
    let mut failed = Ok(());
    let o = path.origin;
    path.walk(|piece| {
        if failed.is_err() {
            return;
        }
        points.clear();
        let (is_rapid, tool) = match piece {
            Drawn::Line(is_rapid, pts, last, tool) => {
                for p in pts.iter().chain(&last) {
                    let p = p.map(f64::from);
                    points.push((frame.pixel_of(p), o[d] + p[d]));
                }
                (is_rapid, tool)
            }
            Drawn::Arc(a) => {
                // At most 2 pixels and 22.5° apart.
                let r = f64::from(a.centre[0] - a.from[a.plane.axes().0])
                    .hypot(f64::from(a.centre[1] - a.from[a.plane.axes().1]));
                let sweep = f64::from(a.sweep).abs();
                let steps = (sweep * r * frame.scale / 2.0)
                    .max(sweep / FRAC_PI_8)
                    .ceil()
                    .clamp(1.0, 1e5) as usize;
                arc_points(&a, steps, |p| points.push((frame.pixel_of(p), o[d] + p[d])));
                (false, a.tool)
            }
        };
        if is_rapid {
            run.clear();
            for &(q, _) in &points {
                push(&mut run, q);
            }
            if run.len() == 1 {
                run.push(run[0]);
            }
            failed = root.draw(&DashedPathElement::new(
                run.iter().copied(),
                u(6) as u32,
                u(4) as u32,
                rapid,
            ));
            return;
        }
        // Each segment takes the colour of its middle's depth (or its tool's).
        run.clear();
        let mut bucket = None;
        for pair in points.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            let here = paint.bucket((a.1 + b.1) / 2.0, tool);
            if bucket != Some(here) {
                if let Some(done) = bucket
                    && run.len() > 1
                {
                    failed = root.draw(&PathElement::new(std::mem::take(&mut run), stroke(done)));
                    if failed.is_err() {
                        return;
                    }
                }
                run.clear();
                run.push(a.0);
                bucket = Some(here);
            }
            push(&mut run, b.0);
        }
        if let [(q, z)] = points[..] {
            run = vec![q, q];
            bucket = Some(paint.bucket(z, tool));
        }
        if let Some(done) = bucket {
            if run.len() == 1 {
                run.push(run[0]);
            }
            failed = root.draw(&PathElement::new(std::mem::take(&mut run), stroke(done)));
        }
    });
    failed?;
    // A hole seen end-on is a point: each gets a ring of 4 pixels, coloured as its bottom.
    if let Some(n) = view.normal() {
        for (axis, p, tool) in &path.plunges {
            if usize::from(*axis) == n {
                let p = p.map(f64::from);
                let ring = stroke(paint.bucket(o[d] + p[d], *tool));
                root.draw(&Circle::new(frame.pixel_of(p), u(4), ring))?;
            }
        }
    }
    let mut labels = Vec::new();
    for (i, line) in header.into_iter().enumerate() {
        labels.push(Label::left(line, u(SIDE), u(6 + i as i32 * LINE)));
    }
    // The scale bar, bottom left: a round length about a fifth of the drawing's width.
    let length = round_length(f64::from(x1 - x0) / 5.0 / (frame.scale / f64::from(unit)) * k);
    let pixels = (length / k * frame.scale / f64::from(unit)).round() as i32;
    let (bx, by) = (SIDE, h - 16);
    let bar = ShapeStyle::from(&BLACK).stroke_width(u(2) as u32);
    root.draw(&PathElement::new(
        vec![(u(bx), u(by)), (u(bx + pixels), u(by))],
        bar,
    ))?;
    for x in [bx, bx + pixels] {
        root.draw(&PathElement::new(
            vec![(u(x), u(by - 5)), (u(x), u(by + 5))],
            bar,
        ))?;
    }
    let label = match view {
        View::Iso => format!("{} {units} (picture plane)", trim(length)),
        _ => format!("{} {units}", trim(length)),
    };
    labels.push(Label::left(label, u(bx + pixels + 8), u(by - 9)));
    // The legend: right-aligned beside the bar, or rows from the left above it.
    for (r, row) in rows.iter().enumerate() {
        let y = if side_by_side {
            by
        } else {
            by - (rows.len() - r) as i32 * LINE
        };
        let mut x = if side_by_side {
            w - SIDE - (row.iter().map(item_width).sum::<i32>() - GAP)
        } else {
            SIDE
        };
        for item in row {
            let (swatch, name) = item;
            let sw = match swatch {
                Swatch::Solid(c) => {
                    let style = ShapeStyle::from(c).stroke_width(u(1) as u32);
                    root.draw(&PathElement::new(
                        vec![(u(x), u(y)), (u(x + SWATCH), u(y))],
                        style,
                    ))?;
                    SWATCH
                }
                Swatch::Dashed(c) => {
                    let style = ShapeStyle::from(c).stroke_width(u(1) as u32);
                    root.draw(&DashedPathElement::new(
                        [(u(x), u(y)), (u(x + SWATCH), u(y))],
                        u(6) as u32,
                        u(4) as u32,
                        style,
                    ))?;
                    SWATCH
                }
                Swatch::Ramp => {
                    for s in 0..RAMP_SWATCH {
                        let c = ramp(f64::from(s) / f64::from(RAMP_SWATCH - 1));
                        root.draw(&Rectangle::new(
                            [(u(x + s), u(y - 4)), (u(x + s + 1), u(y + 4))],
                            ShapeStyle::from(&c).filled(),
                        ))?;
                    }
                    RAMP_SWATCH
                }
            };
            labels.push(Label::left(name.clone(), u(x + sw + 6), u(y - 9)));
            x += item_width(item);
        }
    }
    Ok(labels)
}

/// Appends `p` unless it is the last pixel already.
#[inline]
fn push(line: &mut Vec<(i32, i32)>, p: (i32, i32)) {
    if line.last() != Some(&p) {
        line.push(p);
    }
}

/// The eight corners of a box (least, greatest X Y Z): bit 0 of the index takes X's greatest, bit
/// 1 Y's, bit 2 Z's.
fn box_corners(b: &[[f64; 3]; 2]) -> [[f64; 3]; 8] {
    std::array::from_fn(|i| [0, 1, 2].map(|k| b[(i >> k) & 1][k]))
}

/// Calls `f` with `steps + 1` points of the arc `a` (offsets, X Y Z), from its start to its end.
fn arc_points(a: &ArcPiece, steps: usize, mut f: impl FnMut([f64; 3])) {
    let steps = steps.max(1);
    let (ia, ib, n) = a.plane.axes();
    let from = a.from.map(f64::from);
    let (ca, cb) = (f64::from(a.centre[0]), f64::from(a.centre[1]));
    let r = (from[ia] - ca).hypot(from[ib] - cb);
    let start = (from[ib] - cb).atan2(from[ia] - ca);
    let sweep = f64::from(a.sweep);
    for s in 0..=steps {
        let t = s as f64 / steps as f64;
        let (sin, cos) = (start + sweep * t).sin_cos();
        let mut p = from;
        p[ia] = ca + r * cos;
        p[ib] = cb + r * sin;
        p[n] = from[n] + f64::from(a.rise) * t;
        f(p);
    }
}

/// The largest 1, 2 or 5 × 10ⁿ that is at most `x` (x > 0).
fn round_length(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return 1.0;
    }
    let decade = 10f64.powf(x.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&l| l <= x * (1.0 + 1e-9))
        .unwrap_or(decade)
}

/// A round length without trailing zeros (`0.5`, `20`).
fn trim(x: f64) -> String {
    let s = format!("{x:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

impl fmsvm_canon::Emitter for Recorder {
    const CANON: bool = true;

    fn canon(&mut self, op: &Canon<'_>, _: fmsvm_canon::Origin) -> Result<(), fmsvm_block::Stop> {
        if op.is_block() {
            self.budget.spend_line(0)?;
        }
        if let Some(to) = op.end() {
            self.reach.check(to, self.inch)?;
        }
        self.op(op);
        Ok(())
    }
}

#[cfg(test)]
mod tests;
