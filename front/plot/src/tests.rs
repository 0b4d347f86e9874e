use super::*;

const R: f64 = 40.0;

fn p(x: f64, y: f64, z: f64) -> Pose {
    [x, y, z, 0.0, 0.0, 0.0]
}

/// The hemisphere raster (rows 1 apart in Y, points 0.5 apart in X, zigzag, Z on a R40 dome and 0
/// outside it), a full circle R45 round it at Z0 and a helix above, between rapids at Z50.
fn hemisphere() -> (Recorder, usize) {
    let mut r = Recorder::new();
    let mut moves = 0;
    let mut op = |r: &mut Recorder, c: Canon<'_>| {
        r.op(&c);
        moves += 1;
    };
    op(&mut r, Canon::Rapid(p(-R, -R, 50.0)));
    op(&mut r, Canon::Rapid(p(-R, -R, 0.0)));
    op(&mut r, Canon::FeedRate(1000.0));
    for row in 0..=80 {
        let y = row as f64 - R;
        for i in 0..=160 {
            let i = if row % 2 == 0 { i } else { 160 - i };
            let x = i as f64 * 0.5 - R;
            let z = (R * R - x * x - y * y).max(0.0).sqrt();
            op(&mut r, Canon::Feed(p(x, y, z)));
        }
    }
    op(&mut r, Canon::Rapid(p(R, R, 50.0)));
    op(&mut r, Canon::Rapid(p(45.0, 0.0, 50.0)));
    op(&mut r, Canon::Rapid(p(45.0, 0.0, 0.0)));
    // A full circle R45 at Z0, counter-clockwise.
    op(
        &mut r,
        Canon::Arc(Arc {
            to: p(45.0, 0.0, 0.0),
            centre: [0.0, 0.0],
            plane: Plane::XY,
            clockwise: false,
            turns: 0,
        }),
    );
    // A helix R10 about the top, two turns rising 4, then a half circle in G18.
    op(&mut r, Canon::Rapid(p(10.0, 0.0, 42.0)));
    op(
        &mut r,
        Canon::Arc(Arc {
            to: p(10.0, 0.0, 46.0),
            centre: [0.0, 0.0],
            plane: Plane::XY,
            clockwise: true,
            turns: 1,
        }),
    );
    op(
        &mut r,
        Canon::Arc(Arc {
            to: p(-10.0, 0.0, 46.0),
            centre: [46.0, 0.0],
            plane: Plane::ZX,
            clockwise: true,
            turns: 0,
        }),
    );
    op(&mut r, Canon::Rapid(p(-10.0, 0.0, 50.0)));
    (r, moves)
}

/// The points of an SVG polyline in pixels (its coordinates are tenths of one: the viewBox).
fn numbers(points: &str) -> Vec<(f64, f64)> {
    let u = f64::from(SVG_UNIT);
    points
        .split_whitespace()
        .filter_map(|pair| {
            let (x, y) = pair.split_once(',')?;
            Some((x.parse::<f64>().ok()? / u, y.parse::<f64>().ok()? / u))
        })
        .collect()
}

#[test]
fn plot_hemisphere_svg() {
    let (rec, moves) = hemisphere();
    assert!(moves > 13_000);
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("dome.svg");
    render(&rec, &out, View::Xy, Colour::Motion, (1200, 900)).expect("rendered");
    let text = std::fs::read_to_string(&out).expect("written");
    let doc = roxmltree::Document::parse(&text).expect("the SVG is XML");
    let svg = doc.root_element();
    assert_eq!(svg.tag_name().name(), "svg");
    assert_eq!(svg.attribute("width"), Some("1200"));
    assert_eq!(svg.attribute("height"), Some("900"));
    // The drawing box is x 16..1184, y 52..856; the path is 90 × 90 mm, so Y fills the height
    // (8.93 px/mm) and X is centred: 198..1002.
    let (mut feed, mut rapid) = (Vec::new(), Vec::new());
    let mut circle = None;
    for node in doc.descendants().filter(|n| n.has_tag_name("polyline")) {
        let pts = numbers(node.attribute("points").unwrap_or(""));
        // The legend and the scale bar are below the drawing box.
        if pts.iter().all(|&(_, y)| y > 860.0) {
            continue;
        }
        let colour = node.attribute("stroke").unwrap_or("");
        let centred = pts.len() > 200
            && pts
                .iter()
                .all(|&(x, y)| ((x - 600.0).hypot(y - 454.0) - 45.0 * 804.0 / 90.0).abs() < 1.5);
        if centred {
            circle = Some(pts.len());
        }
        if colour.eq_ignore_ascii_case("#0054BE") {
            feed.extend(pts);
        } else if colour.eq_ignore_ascii_case("#D64000") {
            rapid.extend(pts);
        } else {
            panic!("a polyline of colour {colour}");
        }
    }
    let extent = |v: &[(f64, f64)]| {
        v.iter()
            .fold([f64::MAX, f64::MIN, f64::MAX, f64::MIN], |e, &(x, y)| {
                [e[0].min(x), e[1].max(x), e[2].min(y), e[3].max(y)]
            })
    };
    let e = extent(&feed);
    assert!(
        (e[0] - 198.0).abs() <= 1.0 && (e[1] - 1002.0).abs() <= 1.0,
        "{e:?}"
    );
    assert!(
        (e[2] - 52.0).abs() <= 1.0 && (e[3] - 856.0).abs() <= 1.0,
        "{e:?}"
    );
    // The circle is drawn as an arc, finely sampled (at most 2 px apart: over 1000 points).
    assert!(circle.is_some_and(|n| n > 1000), "{circle:?}");
    // Rapids are dashed: many short pieces, inside the drawing box.
    assert!(!rapid.is_empty());
    let r = extent(&rapid);
    assert!(
        r[0] >= 197.0 && r[1] <= 1003.0 && r[2] >= 51.0 && r[3] <= 857.0,
        "{r:?}"
    );
    // The extents and the scale as text.
    let texts: Vec<String> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.text().unwrap_or("").trim().to_string())
        .collect();
    assert!(texts.iter().any(|t| t == "XY view, mm"), "{texts:?}");
    assert!(
        texts
            .iter()
            .any(|t| t == "X -45.000 .. 45.000   Y -45.000 .. 45.000"),
        "{texts:?}"
    );
    // A fifth of the box is 26 mm: the bar is 20 mm.
    assert!(texts.iter().any(|t| t == "20 mm"), "{texts:?}");
}

#[test]
fn plot_hemisphere_png() {
    let (rec, _) = hemisphere();
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("dome.PNG");
    render(&rec, &out, View::Xy, Colour::Motion, (1200, 900)).expect("rendered");
    let file = std::fs::File::open(&out).expect("written");
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .expect("a PNG");
    let mut pixels = vec![0; decoder.output_buffer_size().expect("size")];
    let info = decoder.next_frame(&mut pixels).expect("decoded");
    assert_eq!((info.width, info.height), (1200, 900));
    assert_eq!(info.color_type, png::ColorType::Rgb);
    let at = |x: usize, y: usize| {
        let i = (y * 1200 + x) * 3;
        (pixels[i], pixels[i + 1], pixels[i + 2])
    };
    const WHITE: (u8, u8, u8) = (255, 255, 255);
    // The raster row Y0 crosses the middle: X −40…40 is pixels 243…957 on row 454.
    for x in [300, 600, 900] {
        assert_ne!(at(x, 454), WHITE, "x {x}");
    }
    // Inside the box of the path but off it: X44 Y44 (outside the raster and the circle).
    assert_eq!(at(993, 61), WHITE);
    assert_eq!(at(5, 450), WHITE);
    // The extents text is drawn with the embedded font: dark pixels in the top band.
    let dark = (0..46)
        .flat_map(|y| (16..700).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let (r, g, b) = at(x, y);
            (r as u32 + g as u32 + b as u32) < 300
        })
        .count();
    assert!(dark > 200, "{dark} dark pixels of text");
}

#[test]
fn plot_views_show_their_axes() {
    let (rec, _) = hemisphere();
    for (view, first, label) in [
        (
            View::Xz,
            "X -45.000 .. 45.000   Z 0.000 .. 56.000",
            "XZ view, mm",
        ),
        (
            View::Yz,
            "Y -45.000 .. 45.000   Z 0.000 .. 56.000",
            "YZ view, mm",
        ),
        (
            View::Iso,
            "X -45.000 .. 45.000   Y -45.000 .. 45.000   Z 0.000 .. 56.000",
            "isometric view, mm",
        ),
    ] {
        let svg = picture(&rec, Format::Svg, view, Colour::Motion, (800, 600)).expect("drawn");
        let svg = String::from_utf8(svg).expect("UTF-8");
        let doc = roxmltree::Document::parse(&svg).expect("XML");
        let texts: Vec<&str> = doc
            .descendants()
            .filter(|n| n.has_tag_name("text"))
            .filter_map(|n| n.text().map(str::trim))
            .collect();
        assert!(texts.contains(&first), "{view:?}: {texts:?}");
        assert!(texts.contains(&label), "{view:?}: {texts:?}");
        // Every point of the path is inside the picture.
        for node in doc.descendants().filter(|n| n.has_tag_name("polyline")) {
            for (x, y) in numbers(node.attribute("points").unwrap_or("")) {
                assert!((0.0..=800.0).contains(&x) && (0.0..=600.0).contains(&y));
            }
        }
    }
}

#[test]
fn plot_inch_and_empty() {
    // An inch program is labelled in inches.
    let mut rec = Recorder::new();
    rec.op(&Canon::Units(true));
    rec.op(&Canon::Feed(p(2.0, 1.0, 0.0)));
    let svg = String::from_utf8(
        picture(&rec, Format::Svg, View::Xy, Colour::Motion, (400, 300)).expect("drawn"),
    )
    .expect("UTF-8");
    assert!(
        svg.contains("X 0.0000 .. 2.0000   Y 0.0000 .. 1.0000"),
        "{svg}"
    );
    assert!(svg.contains("XY view, in"));
    // Nothing moved: a picture that says so.
    let svg = picture(
        &Recorder::new(),
        Format::Svg,
        View::Iso,
        Colour::Motion,
        (400, 300),
    )
    .expect("drawn");
    assert!(String::from_utf8_lossy(&svg).contains("no motion"));
    // A size out of range and a name without a picture's extension are refused.
    assert!(picture(&rec, Format::Png, View::Xy, Colour::Motion, (0, 300)).is_err());
    let dir = tempfile::tempdir().expect("temp dir");
    assert!(
        render(
            &rec,
            &dir.path().join("x.jpg"),
            View::Xy,
            Colour::Motion,
            (400, 300)
        )
        .is_err()
    );
}

#[test]
fn plot_thins_points_closer_than_a_cell() {
    // A million moves 0.0001 apart along 100 mm keep a few tens of thousands of points, and the
    // picture still reaches both ends.
    let mut rec = Recorder::new();
    for i in 1..=1_000_000 {
        rec.op(&Canon::Feed(p(i as f64 * 1e-4, 0.0, 0.0)));
    }
    assert!(rec.kept_points() < 60_000, "{}", rec.kept_points());
    let b = rec.bounds().expect("moved");
    assert_eq!((b.min[0], b.max[0]), (0.0, 100.0));
    let svg = String::from_utf8(
        picture(&rec, Format::Svg, View::Xy, Colour::Motion, (1200, 900)).expect("drawn"),
    )
    .expect("UTF-8");
    let doc = roxmltree::Document::parse(&svg).expect("XML");
    let xs: Vec<f64> = doc
        .descendants()
        .filter(|n| n.has_tag_name("polyline"))
        .flat_map(|n| numbers(n.attribute("points").unwrap_or("")))
        .filter(|&(_, y)| y < 860.0)
        .map(|(x, _)| x)
        .collect();
    let lo = xs.iter().copied().fold(f64::MAX, f64::min);
    let hi = xs.iter().copied().fold(f64::MIN, f64::max);
    assert_eq!((lo, hi), (16.0, 1184.0));
    // Tiny arcs become points of the polyline; a visible one stays an arc.
    let mut rec = Recorder::new();
    rec.op(&Canon::Feed(p(100.0, 100.0, 0.0)));
    rec.op(&Canon::Arc(Arc {
        to: p(100.0, 100.0002, 0.0),
        centre: [100.0, 100.0001],
        plane: Plane::XY,
        clockwise: false,
        turns: 0,
    }));
    assert!(rec.pieces.is_empty() && rec.open == Some((false, 0)));
    rec.op(&Canon::Arc(Arc {
        to: p(100.0, 120.0, 0.0),
        centre: [100.0, 110.0],
        plane: Plane::XY,
        clockwise: false,
        turns: 0,
    }));
    assert!(matches!(
        rec.pieces[..],
        [
            Piece::Line {
                rapid: false,
                end: 3,
                tool: 0
            },
            Piece::Arc(_)
        ]
    ));
}

#[test]
fn plot_round_lengths() {
    assert_eq!(round_length(26.1), 20.0);
    assert_eq!(round_length(7.0), 5.0);
    assert_eq!(round_length(0.31), 0.2);
    assert_eq!(round_length(1.0), 1.0);
    assert_eq!(trim(0.5), "0.5");
    assert_eq!(trim(200.0), "200");
}

/// The text of an SVG picture: each line's box (left, top, right, bottom) in pixels, from its
/// position and the monospace advance.
fn text_boxes(svg: &str) -> Vec<(String, [f64; 4])> {
    let doc = roxmltree::Document::parse(svg).expect("the SVG is XML");
    let u = f64::from(SVG_UNIT);
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| {
            let text = n.text().unwrap_or("").trim().to_string();
            let num = |a| {
                n.attribute(a)
                    .and_then(|v| v.parse::<f64>().ok())
                    .unwrap_or(0.0)
            };
            let (x, y) = (num("x") / u, num("y") / u);
            let w = text.chars().count() as f64 * ADVANCE;
            (text, [x, y, x + w, y + f64::from(LINE) - 2.0])
        })
        .collect()
}

#[test]
fn plot_small_pictures_keep_their_text_inside_and_apart() {
    // At 400×300 every line of text stays inside the picture and no two overlap, in every
    // view and colouring, with a stock box and three tools in the legend; a line that does not
    // fit breaks (the lathe view's name, the extents one an axis).
    let (mut rec, _) = hemisphere();
    rec.stock = Some([[-50.0, -50.0, -10.0], [50.0, 50.0, 0.0]]);
    for t in [1.0, 12.0, 105.0] {
        rec.op(&Canon::Tool(t));
        rec.op(&Canon::Feed(p(0.0, 0.0, t / 10.0)));
    }
    for (w, h) in [(400u32, 300u32), (640, 480)] {
        for view in [View::Xy, View::Xz, View::Yz, View::Iso, View::Zx] {
            for colour in [Colour::Depth, Colour::Tool, Colour::Motion] {
                let svg = String::from_utf8(
                    picture(&rec, Format::Svg, view, colour, (w, h)).expect("drawn"),
                )
                .expect("UTF-8");
                let boxes = text_boxes(&svg);
                assert!(boxes.len() >= 5, "{boxes:?}");
                for (text, b) in &boxes {
                    assert!(
                        b[0] >= 0.0 && b[2] <= f64::from(w) && b[1] >= 0.0 && b[3] <= f64::from(h),
                        "{w}x{h} {view:?} {colour:?}: `{text}` at {b:?} leaves the picture"
                    );
                }
                for (i, (t1, a)) in boxes.iter().enumerate() {
                    for (t2, b) in &boxes[i + 1..] {
                        let apart = a[2] <= b[0] || b[2] <= a[0] || a[3] <= b[1] || b[3] <= a[1];
                        assert!(
                            apart,
                            "{w}x{h} {view:?} {colour:?}: `{t1}` {a:?} and `{t2}` {b:?} overlap"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn plot_svg_keeps_sub_pixel_detail() {
    // A zigzag 0.05 mm high along 100 mm: at 11.7 px/mm it is 0.58 px, which whole pixels
    // would draw as 0 or 1; the SVG's tenths keep it.
    let mut rec = Recorder::new();
    rec.op(&Canon::Rapid(p(0.0, 0.0, 0.0)));
    for i in 1..=100 {
        rec.op(&Canon::Feed(p(f64::from(i), 0.05 * f64::from(i % 2), 0.0)));
    }
    let svg = String::from_utf8(
        picture(&rec, Format::Svg, View::Xy, Colour::Motion, (1200, 900)).expect("drawn"),
    )
    .expect("UTF-8");
    let doc = roxmltree::Document::parse(&svg).expect("XML");
    let ys: Vec<f64> = doc
        .descendants()
        .filter(|n| n.has_tag_name("polyline"))
        .filter(|n| n.attribute("stroke") == Some("#0054BE"))
        .flat_map(|n| numbers(n.attribute("points").unwrap_or("")))
        .filter(|&(_, y)| y < 860.0)
        .map(|(_, y)| y)
        .collect();
    let (lo, hi) = ys
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &y| (a.min(y), b.max(y)));
    let scale = (1200.0 - 32.0) / 100.0;
    assert!(
        ((hi - lo) - 0.05 * scale).abs() <= 0.1,
        "the zigzag is {} px high, {} expected",
        hi - lo,
        0.05 * scale
    );
}

#[test]
fn plot_colours_feed_moves_by_depth_and_by_tool() {
    // Two passes, T1 at Z-10 and T2 at Z0: by depth the deep one is the ramp's dark end and
    // the high one its light end; by tool each its tool's colour.
    let mut rec = Recorder::new();
    rec.op(&Canon::Tool(1.0));
    rec.op(&Canon::Rapid(p(0.0, 0.0, -10.0)));
    rec.op(&Canon::Feed(p(100.0, 0.0, -10.0)));
    rec.op(&Canon::Tool(2.0));
    rec.op(&Canon::Rapid(p(0.0, 50.0, 0.0)));
    rec.op(&Canon::Feed(p(100.0, 50.0, 0.0)));
    let colours = |colour| {
        let svg = String::from_utf8(
            picture(&rec, Format::Svg, View::Xy, colour, (800, 600)).expect("drawn"),
        )
        .expect("UTF-8");
        let doc = roxmltree::Document::parse(&svg).expect("XML");
        let mut by_y: Vec<(f64, String)> = doc
            .descendants()
            .filter(|n| n.has_tag_name("polyline"))
            .filter_map(|n| {
                let pts = numbers(n.attribute("points")?);
                let horizontal =
                    pts.len() == 2 && pts[0].1 == pts[1].1 && (pts[1].0 - pts[0].0).abs() > 100.0;
                let stroke = n.attribute("stroke").unwrap_or("");
                // The scale bar is black.
                (horizontal && stroke != "#000000").then(|| (pts[0].1, stroke.to_string()))
            })
            .collect();
        by_y.sort_by(|a, b| a.0.total_cmp(&b.0));
        by_y.into_iter().map(|(_, c)| c).collect::<Vec<_>>()
    };
    // Top of the picture first: Y50 (Z0, high), then Y0 (Z-10, deep).
    assert_eq!(colours(Colour::Depth), ["#FDE725", "#440154"]);
    assert_eq!(colours(Colour::Tool), ["#008C46", "#0054BE"]);
    assert_eq!(colours(Colour::Motion), ["#0054BE", "#0054BE"]);
    assert_eq!(ramp(0.0), RAMP[0]);
    assert_eq!(ramp(1.0), RAMP[4]);
    assert_eq!(ramp(0.5), RAMP[2]);
}

/// `plot --stock`: a mill's part from above, the slot darker than the uncut top (its depth on the
/// ramp), a rapid into material in red with a ring where it ends; a lathe's half-section solid grey
/// where the bar is left, white where it was cut.
#[test]
fn the_stock_picture_shows_the_cut_the_uncut_and_the_rapid_in_red() {
    use fmsvm_stock::{Cutter, HeightField, MAX_CELLS, Report, Shape, Stock};
    let mut field = HeightField::new([[0.0, 0.0, -10.0], [100.0, 100.0, 0.0]], 0.5, MAX_CELLS)
        .expect("a field");
    field.cut(
        [-10.0, 50.0, -5.0],
        [110.0, 50.0, -5.0],
        &Cutter::new(Shape::Flat, 5.0),
    );
    let report = Report {
        hits: vec![[[20.0, 20.0, 10.0], [20.0, 80.0, 10.0]]],
        ..Report::default()
    };
    // 132 × 132 pixels: a 100 × 100 box in 100 pixels with the 16-pixel margins; Y up.
    let px = stock::pixels(&Stock::Mill(field), &report, (132, 132)).expect("drawn");
    let at = |x: usize, y: usize| {
        let k = (y * 132 + x) * 3;
        [px[k], px[k + 1], px[k + 2]]
    };
    let brightness = |c: [u8; 3]| u32::from(c[0]) + u32::from(c[1]) + u32::from(c[2]);
    // Y50 is pixel row 132 − 16 − 50 = 66; Y20 row 96.
    assert!(
        brightness(at(80, 66)) < brightness(at(80, 96)),
        "{:?} {:?}",
        at(80, 66),
        at(80, 96)
    );
    assert_eq!(at(36, 80), [220, 0, 0]);
    // Outside the box: the page.
    assert_eq!(at(2, 2), [255, 255, 255]);
    let mut bar =
        fmsvm_stock::HalfSection::new([-40.0, 0.0], [0.0, 20.0], 0.5, MAX_CELLS).expect("a bar");
    let nose = fmsvm_stock::Nose::new(0.4, 3, [-0.4, -0.4]);
    bar.cut([15.0, 1.0], [15.0, -20.0], &nose);
    let px = stock::pixels(&Stock::Lathe(bar), &Report::default(), (112, 72)).expect("drawn");
    let at = |x: usize, y: usize| {
        let k = (y * 112 + x) * 3;
        [px[k], px[k + 1], px[k + 2]]
    };
    // Z −40…0 over 80 pixels from x 16 (2 a mm), radius 0…20 over 40 up from row 56.
    // At Z−10 (x 76): radius 17.5 (row 21) is cut, radius 10 (row 36) is solid.
    assert_eq!(at(76, 21), [255, 255, 255]);
    assert_eq!(at(76, 36), [150, 150, 150]);
    // At Z−30 (x 36), the turning did not reach: radius 17.5 solid.
    assert_eq!(at(36, 21), [150, 150, 150]);
}
