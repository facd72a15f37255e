//! Pictures of a world: a `tiny-skia` canvas behind the library's
//! [`DebugDraw`] trait, and PNG output (single frames, and animated PNG for
//! the showcase).
//!
//! **View.** The view is fitted once, to the bounding box of everything the
//! first frame draws (static shapes included, so the ground is in the
//! picture), with a margin, y up. Later frames keep it so that frames line
//! up; bodies that fly out of it are clipped.
//!
//! **Animation.** An animated PNG (APNG): one file that browsers and most
//! image viewers play, and that shows its first frame where APNG is not
//! understood. Written with the `png` crate, which `tiny-skia` already
//! uses, so it costs no extra dependency. Each frame is shown for
//! `every · dt` seconds: the animation plays in real time.
use std::collections::HashMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use tamias2d::debug_draw::{Color, DebugDraw, DebugDrawOptions, Point, ShapeStyle};
use tamias2d::space::Space;
use tiny_skia::{FillRule, LineCap, LineJoin, Paint, PathBuilder, Pixmap, Stroke, Transform};

/// Image width in pixels.
pub const WIDTH: u32 = 960;
/// Blank border around the scene, as a fraction of the image size.
const MARGIN: f64 = 0.05;
/// Thinnest line drawn, in pixels (a zero-radius ground segment).
const MIN_LINE: f64 = 2.0;
/// Background colour.
const BACKGROUND: (u8, u8, u8) = (250, 250, 246);

/// Axis-aligned bounds of drawn primitives, in world units.
#[derive(Clone, Copy, Debug)]
struct Bounds {
    min: Point,
    max: Point,
}

impl Bounds {
    const EMPTY: Bounds = Bounds {
        min: [f64::INFINITY; 2],
        max: [f64::NEG_INFINITY; 2],
    };

    fn add(&mut self, p: Point, r: f64) {
        for ((lo, hi), v) in self.min.iter_mut().zip(&mut self.max).zip(p) {
            *lo = lo.min(v - r);
            *hi = hi.max(v + r);
        }
    }
}

impl DebugDraw for Bounds {
    fn circle(&mut self, center: Point, radius: f64, _rot: Point, _style: ShapeStyle) {
        self.add(center, radius);
    }
    fn segment(&mut self, a: Point, b: Point, radius: f64, _style: ShapeStyle) {
        self.add(a, radius);
        self.add(b, radius);
    }
    fn polygon(&mut self, verts: &[Point], radius: f64, _style: ShapeStyle) {
        for v in verts {
            self.add(*v, radius);
        }
    }
    fn dot(&mut self, _p: Point, _size: f64, _color: Color) {}
}

/// World-to-image mapping: `px = (x − x0)·scale + ox`, `py = (y1 − y)·scale + oy`.
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    scale: f64,
    x0: f64,
    y1: f64,
    ox: f64,
    oy: f64,
}

impl View {
    /// A view of everything `space` draws now, `WIDTH` pixels wide and as
    /// high as the scene's aspect asks (between 0.4 and 1 times the width).
    pub fn fit(space: &Space) -> View {
        let mut b = Bounds::EMPTY;
        space.debug_draw(&mut b, &DebugDrawOptions::default());
        if !(b.min[0].is_finite() && b.max[0].is_finite()) {
            b = Bounds {
                min: [-1.0, -1.0],
                max: [1.0, 1.0],
            };
        }
        let w = (b.max[0] - b.min[0]).max(1e-3);
        let h = (b.max[1] - b.min[1]).max(1e-3);
        let width = WIDTH;
        let aspect = (h / w).clamp(0.4, 1.0);
        // Even height (friendlier to video encoders if someone converts).
        let height = ((f64::from(width) * aspect / 2.0).round() as u32 * 2).max(2);
        let inner_w = f64::from(width) * (1.0 - 2.0 * MARGIN);
        let inner_h = f64::from(height) * (1.0 - 2.0 * MARGIN);
        let scale = (inner_w / w).min(inner_h / h);
        View {
            width,
            height,
            scale,
            x0: b.min[0],
            y1: b.max[1],
            ox: (f64::from(width) - w * scale) / 2.0,
            oy: (f64::from(height) - h * scale) / 2.0,
        }
    }

    fn px(&self, p: Point) -> (f32, f32) {
        (
            ((p[0] - self.x0) * self.scale + self.ox) as f32,
            ((self.y1 - p[1]) * self.scale + self.oy) as f32,
        )
    }

    fn len(&self, r: f64) -> f32 {
        (r * self.scale) as f32
    }
}

/// A picture being drawn.
pub struct Canvas {
    view: View,
    pixmap: Pixmap,
    options: DebugDrawOptions,
}

fn paint(c: Color) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color_rgba8(c.r, c.g, c.b, c.a);
    p.anti_alias = true;
    p
}

fn stroke(width: f32) -> Stroke {
    Stroke {
        width,
        line_cap: LineCap::Round,
        line_join: LineJoin::Round,
        ..Stroke::default()
    }
}

impl Canvas {
    /// A blank canvas for `view`.
    pub fn new(view: View) -> Result<Canvas, String> {
        let pixmap = Pixmap::new(view.width, view.height)
            .ok_or_else(|| format!("cannot make a {}x{} image", view.width, view.height))?;
        let options = DebugDrawOptions {
            contacts: true,
            contact_size: 3.0,
            ..DebugDrawOptions::default()
        };
        Ok(Canvas {
            view,
            pixmap,
            options,
        })
    }

    /// Clears the canvas and draws `space` on it (shapes and contacts).
    pub fn draw(&mut self, space: &Space) {
        let (r, g, b) = BACKGROUND;
        self.pixmap.fill(tiny_skia::Color::from_rgba8(r, g, b, 255));
        let options = self.options;
        space.debug_draw(self, &options);
    }

    /// The picture as 8-bit RGB rows (the background is opaque, so the
    /// premultiplied RGBA of the pixmap is plain RGBA and alpha can go).
    pub fn rgb(&self) -> Vec<u8> {
        self.pixmap
            .data()
            .chunks_exact(4)
            .flat_map(|px| px.iter().take(3).copied())
            .collect()
    }

    /// Writes the picture to `path` as a PNG.
    pub fn write_png(&self, path: &Path) -> Result<(), String> {
        let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
        let file = File::create(path).map_err(|e| err(&e))?;
        let mut enc = png::Encoder::new(BufWriter::new(file), self.view.width, self.view.height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().map_err(|e| err(&e))?;
        w.write_image_data(&self.rgb()).map_err(|e| err(&e))?;
        w.finish().map_err(|e| err(&e))
    }

    fn fill_and_outline(&mut self, path: &tiny_skia::Path, radius: f32, style: ShapeStyle) {
        let t = Transform::identity();
        if radius > 0.0 {
            // Rounded shape: a thick stroke of the outline colour, a thinner
            // one of the fill, then the fill.
            self.pixmap.stroke_path(
                path,
                &paint(style.outline),
                &stroke(2.0 * radius + 2.0),
                t,
                None,
            );
            self.pixmap
                .stroke_path(path, &paint(style.fill), &stroke(2.0 * radius), t, None);
            self.pixmap
                .fill_path(path, &paint(style.fill), FillRule::Winding, t, None);
        } else {
            self.pixmap
                .fill_path(path, &paint(style.fill), FillRule::Winding, t, None);
            self.pixmap
                .stroke_path(path, &paint(style.outline), &stroke(1.0), t, None);
        }
    }
}

impl DebugDraw for Canvas {
    fn circle(&mut self, center: Point, radius: f64, rot: Point, style: ShapeStyle) {
        let (x, y) = self.view.px(center);
        let r = self.view.len(radius).max(1.0);
        let Some(path) = PathBuilder::from_circle(x, y, r) else {
            return;
        };
        self.fill_and_outline(&path, 0.0, style);
        // A radius towards the body's angle, so spin shows.
        let mut pb = PathBuilder::new();
        pb.move_to(x, y);
        pb.line_to(x + r * rot[0] as f32, y - r * rot[1] as f32);
        if let Some(line) = pb.finish() {
            let w = (r / 8.0).clamp(1.0, 3.0);
            self.pixmap.stroke_path(
                &line,
                &paint(style.outline),
                &stroke(w),
                Transform::identity(),
                None,
            );
        }
    }

    fn segment(&mut self, a: Point, b: Point, radius: f64, style: ShapeStyle) {
        let (ax, ay) = self.view.px(a);
        let (bx, by) = self.view.px(b);
        let mut pb = PathBuilder::new();
        pb.move_to(ax, ay);
        pb.line_to(bx, by);
        let Some(path) = pb.finish() else {
            return;
        };
        let w = (2.0 * self.view.len(radius)).max(MIN_LINE as f32);
        let t = Transform::identity();
        self.pixmap
            .stroke_path(&path, &paint(style.outline), &stroke(w + 2.0), t, None);
        self.pixmap
            .stroke_path(&path, &paint(style.fill), &stroke(w), t, None);
    }

    fn polygon(&mut self, verts: &[Point], radius: f64, style: ShapeStyle) {
        let mut pb = PathBuilder::new();
        for (i, v) in verts.iter().enumerate() {
            let (x, y) = self.view.px(*v);
            if i == 0 {
                pb.move_to(x, y);
            } else {
                pb.line_to(x, y);
            }
        }
        pb.close();
        if let Some(path) = pb.finish() {
            let r = self.view.len(radius);
            self.fill_and_outline(&path, r, style);
        }
    }

    fn dot(&mut self, p: Point, size: f64, color: Color) {
        let (x, y) = self.view.px(p);
        if let Some(path) = PathBuilder::from_circle(x, y, (size / 2.0) as f32) {
            self.pixmap.fill_path(
                &path,
                &paint(color),
                FillRule::Winding,
                Transform::identity(),
                None,
            );
        }
    }
}

/// A 256-colour palette for animation frames: the drawing's own colours
/// (background, fills, outlines, contact dots) and two blends of every pair
/// of them, which is what anti-aliased edges are made of. Each pixel maps to
/// the nearest entry. Indexed frames compress several times better than RGB
/// and the picture looks the same.
struct Quantizer {
    palette: Vec<[u8; 3]>,
    cache: HashMap<[u8; 3], u8>,
}

impl Quantizer {
    fn new(options: &DebugDrawOptions) -> Quantizer {
        let rgb = |c: Color| [c.r, c.g, c.b];
        let (r, g, b) = BACKGROUND;
        let mut pure = vec![[r, g, b]];
        let styles = [
            options.static_style,
            options.kinematic_style,
            options.sleeping_style,
        ];
        for style in styles {
            pure.extend([rgb(style.fill), rgb(style.outline)]);
        }
        for fill in options.dynamic_fills {
            pure.extend([rgb(fill), rgb(fill.darker())]);
        }
        pure.push(rgb(options.contact_color));
        pure.dedup();
        let mut palette = pure.clone();
        'pairs: for (i, p) in pure.iter().enumerate() {
            for q in pure.iter().skip(i + 1) {
                for t in [1u16, 2] {
                    if palette.len() >= 256 {
                        break 'pairs;
                    }
                    let mix =
                        |a: u8, b: u8| ((u16::from(a) * (3 - t) + u16::from(b) * t) / 3) as u8;
                    palette.push([mix(p[0], q[0]), mix(p[1], q[1]), mix(p[2], q[2])]);
                }
            }
        }
        Quantizer {
            palette,
            cache: HashMap::new(),
        }
    }

    fn index(&mut self, c: [u8; 3]) -> u8 {
        if let Some(i) = self.cache.get(&c) {
            return *i;
        }
        let dist = |p: &[u8; 3]| {
            p.iter()
                .zip(c)
                .map(|(a, b)| (i32::from(*a) - i32::from(b)).pow(2))
                .sum::<i32>()
        };
        let best = (0..self.palette.len())
            .min_by_key(|i| self.palette.get(*i).map_or(i32::MAX, dist))
            .unwrap_or(0);
        let best = u8::try_from(best).unwrap_or(0);
        self.cache.insert(c, best);
        best
    }

    /// The canvas as palette indices, one byte per pixel.
    fn indices(&mut self, canvas: &Canvas) -> Vec<u8> {
        // Runs of one colour are the common case: look up only on a change.
        let mut last = None;
        canvas
            .pixmap
            .data()
            .chunks_exact(4)
            .map(|px| {
                let c = [px[0], px[1], px[2]];
                match last {
                    Some((prev, i)) if prev == c => i,
                    _ => {
                        let i = self.index(c);
                        last = Some((c, i));
                        i
                    }
                }
            })
            .collect()
    }

    fn palette_bytes(&self) -> Vec<u8> {
        self.palette.iter().flatten().copied().collect()
    }
}

/// An animated PNG written frame by frame (the frame count is fixed up
/// front, as APNG's header needs it). Frames are indexed (see
/// [`Quantizer`]); after the first, each frame stores only the rectangle
/// that changed (the rest of the image stays, APNG's "dispose: none"), so a
/// pile at rest costs almost nothing.
pub struct Apng {
    writer: png::Writer<BufWriter<File>>,
    path: String,
    width: u32,
    quantizer: Quantizer,
    previous: Option<Vec<u8>>,
    frames_left: u32,
}

/// Smallest `(x, y, w, h)` holding every pixel where the rows `a` and `b`
/// (of `width` one-byte pixels) differ; a 1×1 corner when they are equal
/// (APNG frames cannot be empty).
fn changed_rect(a: &[u8], b: &[u8], width: u32) -> (u32, u32, u32, u32) {
    let row = width as usize;
    let mut rect: Option<(usize, usize, usize, usize)> = None;
    for (y, (ra, rb)) in a.chunks_exact(row).zip(b.chunks_exact(row)).enumerate() {
        if ra == rb {
            continue;
        }
        let first = ra.iter().zip(rb).position(|(p, q)| p != q).unwrap_or(0);
        let last = row
            - 1
            - ra.iter()
                .zip(rb)
                .rev()
                .position(|(p, q)| p != q)
                .unwrap_or(0);
        rect = Some(match rect {
            None => (first, y, last, y),
            Some((x0, y0, x1, _)) => (x0.min(first), y0, x1.max(last), y),
        });
    }
    let to_u32 = |v: usize| u32::try_from(v).unwrap_or(u32::MAX);
    match rect {
        None => (0, 0, 1, 1),
        Some((x0, y0, x1, y1)) => (
            to_u32(x0),
            to_u32(y0),
            to_u32(x1 - x0 + 1),
            to_u32(y1 - y0 + 1),
        ),
    }
}

/// The `w × h` block at `(x, y)` of rows `data` of `width` one-byte pixels.
fn crop(data: &[u8], width: u32, (x, y, w, h): (u32, u32, u32, u32)) -> Vec<u8> {
    let (x, w) = (x as usize, w as usize);
    data.chunks_exact(width as usize)
        .skip(y as usize)
        .take(h as usize)
        .flat_map(|r| r.get(x..x + w).unwrap_or(&[]).iter().copied())
        .collect()
}

impl Apng {
    /// Starts `path` for `frames` frames of `canvas`'s size and colours,
    /// each shown `delay.0 / delay.1` seconds, looping forever.
    pub fn create(
        path: &Path,
        canvas: &Canvas,
        frames: u32,
        delay: (u16, u16),
    ) -> Result<Apng, String> {
        let name = path.display().to_string();
        let err = |e: &dyn std::fmt::Display| format!("{name}: {e}");
        let quantizer = Quantizer::new(&canvas.options);
        let file = File::create(path).map_err(|e| err(&e))?;
        let (width, height) = (canvas.view.width, canvas.view.height);
        let mut enc = png::Encoder::new(BufWriter::new(file), width, height);
        enc.set_color(png::ColorType::Indexed);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_palette(quantizer.palette_bytes());
        enc.set_compression(png::Compression::Balanced);
        enc.set_animated(frames.max(1), 0).map_err(|e| err(&e))?;
        enc.set_frame_delay(delay.0, delay.1).map_err(|e| err(&e))?;
        let writer = enc.write_header().map_err(|e| err(&e))?;
        Ok(Apng {
            writer,
            path: name,
            width,
            quantizer,
            previous: None,
            frames_left: frames.max(1),
        })
    }

    /// Appends the canvas as the next frame.
    pub fn push(&mut self, canvas: &Canvas) -> Result<(), String> {
        if self.frames_left == 0 {
            return Err(format!("{}: more frames than announced", self.path));
        }
        self.frames_left -= 1;
        let pixels = self.quantizer.indices(canvas);
        let rect = match &self.previous {
            None => (0, 0, canvas.view.width, canvas.view.height),
            Some(prev) => changed_rect(prev, &pixels, self.width),
        };
        let path = &self.path;
        let err = |e: png::EncodingError| format!("{path}: {e}");
        // Position (0, 0) first, so that any new size fits, then the size.
        self.writer.reset_frame_position().map_err(err)?;
        self.writer
            .set_frame_dimension(rect.2, rect.3)
            .map_err(err)?;
        self.writer
            .set_frame_position(rect.0, rect.1)
            .map_err(err)?;
        self.writer
            .write_image_data(&crop(&pixels, self.width, rect))
            .map_err(err)?;
        self.previous = Some(pixels);
        Ok(())
    }

    /// Ends the file; every announced frame must have been pushed.
    pub fn finish(self) -> Result<(), String> {
        if self.frames_left != 0 {
            return Err(format!(
                "{}: {} frames missing",
                self.path, self.frames_left
            ));
        }
        let path = self.path;
        // `finish` writes the end chunk and flushes the file.
        self.writer.finish().map_err(|e| format!("{path}: {e}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tamias2d_scenes as scenes;

    #[test]
    fn view_fits_pyramid_with_ground_inside() {
        let scene = scenes::builtin("pyramid_20").unwrap().build().unwrap();
        let view = View::fit(&scene.space);
        assert_eq!(view.width, WIDTH);
        // 40 m of ground and 20 m of pyramid: 2:1.
        assert_eq!(view.height, WIDTH / 2);
        let (gx0, gy) = view.px([-20.0, 0.0]);
        let (gx1, _) = view.px([20.0, 0.0]);
        assert!(gx0 > 0.0 && gx1 < WIDTH as f32);
        assert!(gy > 0.0 && gy < view.height as f32);
        let (_, top) = view.px([0.0, 20.0]);
        assert!(top < gy, "y points up");
    }

    #[test]
    fn canvas_draws_something_other_than_background() {
        let scene = scenes::builtin("stack_10").unwrap().build().unwrap();
        let mut canvas = Canvas::new(View::fit(&scene.space)).unwrap();
        canvas.draw(&scene.space);
        let rgb = canvas.rgb();
        let (r, g, b) = BACKGROUND;
        let painted = rgb.chunks_exact(3).filter(|p| *p != [r, g, b]).count();
        assert!(painted > 1000, "{painted} pixels painted");
    }

    #[test]
    fn changed_rect_bounds_the_difference() {
        let (w, h) = (5u32, 4u32);
        let a = vec![0u8; (w * h) as usize];
        assert_eq!(changed_rect(&a, &a, w), (0, 0, 1, 1));
        let mut b = a.clone();
        b[(w + 1) as usize] = 9; // pixel (1, 1)
        b[(2 * w + 3) as usize] = 9; // pixel (3, 2)
        let rect = changed_rect(&a, &b, w);
        assert_eq!(rect, (1, 1, 3, 2));
        assert_eq!(crop(&b, w, rect), vec![9, 0, 0, 0, 0, 9]);
    }

    #[test]
    fn quantizer_keeps_pure_colours_exact() {
        let options = DebugDrawOptions::default();
        let mut q = Quantizer::new(&options);
        assert!(q.palette.len() <= 256);
        for c in options.dynamic_fills {
            let i = q.index([c.r, c.g, c.b]);
            assert_eq!(q.palette[usize::from(i)], [c.r, c.g, c.b]);
        }
    }
}
