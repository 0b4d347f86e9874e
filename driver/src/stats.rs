//! `fmsvm stats`: the motion statistics of a run ([`fmsvm_emit::stats::Report`]) written as text
//! for a person or as JSON for a program.

use std::io::{self, Write};

use fmsvm_emit::stats::Report;
use serde::Serialize;

/// Writes `r` (and what the stock saw, when it was simulated) to `out`: aligned text, or one JSON
/// document (`json`).
pub fn report(
    r: &Report,
    stock: Option<&fmsvm_stock::Report>,
    json: bool,
    out: &mut dyn Write,
) -> io::Result<()> {
    if json {
        let mut doc = Json::of(r);
        doc.stock = stock.map(StockJson::of);
        let doc = serde_json::to_string_pretty(&doc).map_err(io::Error::other)?;
        writeln!(out, "{doc}")
    } else {
        out.write_all(text(r).as_bytes())?;
        match stock {
            Some(s) => out.write_all(stock_text(s, r.inch).as_bytes()),
            None => Ok(()),
        }
    }
}

/// The stock's part of the text report: what was removed, each tool's cutting against its feed
/// through air, and the findings counted.
pub fn stock_text(s: &fmsvm_stock::Report, inch: bool) -> String {
    let unit = if inch { "in" } else { "mm" };
    let d = if inch { 4 } else { 3 };
    let removed = s.before - s.after;
    let share = if s.before > 0.0 {
        100.0 * removed / s.before
    } else {
        0.0
    };
    let mut t = format!(
        "{:<13}removed {removed:.d$} {unit}³ of {:.d$} ({share:.1} %), {:.d$} {unit}³ left\n",
        "stock", s.before, s.after
    );
    for (n, tool) in &s.tools {
        t.push_str(&format!(
            "{:<13}removed {:.d$} {unit}³; feed in material {:.d$} {unit} ({}), in air {:.d$} {unit} ({})\n",
            format!("  T{n}"),
            tool.removed,
            tool.cutting_length,
            clock(tool.cutting_seconds),
            tool.air_length,
            clock(tool.air_seconds)
        ));
    }
    t.push_str(&format!(
        "{:<13}{} rapid{} into material, {} cut{} below the floor, {} shank rub{}, {} plunge{} with a tool that cannot\n",
        "findings",
        s.rapids_into_material,
        plural(u64::from(s.rapids_into_material)),
        s.below_floor,
        plural(u64::from(s.below_floor)),
        s.shank_rubs,
        plural(u64::from(s.shank_rubs)),
        s.plunges,
        plural(u64::from(s.plunges)),
    ));
    t
}

/// The report as lines of text.
pub fn text(r: &Report) -> String {
    let unit = if r.inch { "in" } else { "mm" };
    let d = if r.inch { 4 } else { 3 };
    let mut s = String::new();
    let mut line = |label: &str, value: String| {
        s.push_str(&format!("{label:<13}{value}\n"));
    };
    line(
        "moves",
        format!("{} rapid, {} feed, {} arc", r.rapids, r.feeds, r.arcs),
    );
    line(
        "length",
        format!(
            "rapid {:.d$} {unit}, feed {:.d$} {unit} (arcs {:.d$} {unit})",
            r.rapid_length, r.feed_length, r.arc_length
        ),
    );
    match &r.bounds {
        Some(b) => {
            let names = fmsvm_canon::AXES.map(|l| l.as_str());
            // A lathe's X as the program writes it (a diameter), and no Y.
            let (x_scale, x_name, linear): (f64, &str, &[usize]) = match r.turning {
                Some(true) => (2.0, "X (diameter)", &[0, 2]),
                Some(false) => (1.0, "X (radius)", &[0, 2]),
                None => (1.0, "X", &[0, 1, 2]),
            };
            // An axis the program never positioned has no extent (its box is empty).
            let mut axes: Vec<String> = linear
                .iter()
                .map(|&i| {
                    let (k, name) = if i == 0 {
                        (x_scale, x_name)
                    } else {
                        (1.0, names[i])
                    };
                    if b.min[i] > b.max[i] {
                        format!("{name} not positioned")
                    } else {
                        format!("{name} {:.d$} .. {:.d$}", b.min[i] * k, b.max[i] * k)
                    }
                })
                .collect();
            // Rotary axes only when they moved (degrees).
            for (i, name) in names.iter().enumerate().skip(3) {
                if b.min[i] <= b.max[i] && (b.max[i] > b.min[i] || b.min[i] != 0.0) {
                    axes.push(format!("{name} {:.3} .. {:.3} deg", b.min[i], b.max[i]));
                }
            }
            line(
                "extents",
                format!("{}  {unit} (the tool tip)", axes.join("  ")),
            );
        }
        None => line("extents", "no motion".into()),
    }
    line(
        "time",
        format!(
            "{} (rapid {:.1} s at {} mm/min, feed {:.1} s, dwell {:.1} s)",
            clock(r.total_seconds),
            r.rapid_seconds,
            r.rapid_rate,
            r.feed_seconds,
            r.dwell_seconds
        ),
    );
    if r.untimed_feeds > 0 {
        line(
            "not timed",
            format!(
                "{} feed move{} ({:.d$} {unit}) with no feed rate, or G95 without a spindle speed",
                r.untimed_feeds,
                if r.untimed_feeds == 1 { "" } else { "s" },
                r.untimed_length
            ),
        );
    }
    line("tool changes", r.tool_changes.to_string());
    line(
        "codes",
        format!(
            "{} M code{}, {} dwell{}, {} comment{}",
            r.m_codes,
            plural(r.m_codes),
            r.dwells,
            plural(r.dwells),
            r.comments,
            plural(r.comments)
        ),
    );
    s
}

fn plural(n: u64) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// `h:mm:ss` (rounded to the second).
fn clock(seconds: f64) -> String {
    if !seconds.is_finite() {
        return "unknown".into();
    }
    let t = seconds.max(0.0).round() as u64;
    format!("{}:{:02}:{:02}", t / 3600, t / 60 % 60, t % 60)
}

/// The JSON document: the report's fields grouped (counts, lengths, extents, time).
#[derive(Serialize)]
struct Json {
    units: &'static str,
    counts: Counts,
    length: Lengths,
    /// `null` when nothing moved.
    extents: Option<Extents>,
    time: Time,
    /// With --stock: what the material simulation saw.
    #[serde(skip_serializing_if = "Option::is_none")]
    stock: Option<StockJson>,
}

#[derive(Serialize)]
struct StockJson {
    before: f64,
    after: f64,
    removed: f64,
    tools: Vec<StockTool>,
    rapids_into_material: u32,
    below_floor: u32,
    shank_rubs: u32,
    plunges: u32,
}

#[derive(Serialize)]
struct StockTool {
    tool: u32,
    removed: f64,
    cutting_length: f64,
    air_length: f64,
    cutting_s: f64,
    air_s: f64,
    rapids_into_material: u32,
}

impl StockJson {
    fn of(s: &fmsvm_stock::Report) -> StockJson {
        StockJson {
            before: s.before,
            after: s.after,
            removed: s.before - s.after,
            tools: s
                .tools
                .iter()
                .map(|(n, t)| StockTool {
                    tool: *n,
                    removed: t.removed,
                    cutting_length: t.cutting_length,
                    air_length: t.air_length,
                    cutting_s: t.cutting_seconds,
                    air_s: t.air_seconds,
                    rapids_into_material: t.rapids_into_material,
                })
                .collect(),
            rapids_into_material: s.rapids_into_material,
            below_floor: s.below_floor,
            shank_rubs: s.shank_rubs,
            plunges: s.plunges,
        }
    }
}

#[derive(Serialize)]
struct Counts {
    rapid: u64,
    feed: u64,
    arc: u64,
    dwell: u64,
    tool_change: u64,
    m_code: u64,
    comment: u64,
}

#[derive(Serialize)]
struct Lengths {
    rapid: f64,
    feed: f64,
    arc: f64,
    untimed: f64,
}

#[derive(Serialize)]
struct Axes {
    x: f64,
    y: f64,
    z: f64,
    a: f64,
    b: f64,
    c: f64,
}

#[derive(Serialize)]
struct Extents {
    min: Axes,
    max: Axes,
}

#[derive(Serialize)]
struct Time {
    total_s: f64,
    rapid_s: f64,
    feed_s: f64,
    dwell_s: f64,
    rapid_rate_mm_min: f64,
    untimed_feeds: u64,
}

impl Json {
    fn of(r: &Report) -> Json {
        let axes = |p: &[f64; 6]| Axes {
            x: p[0],
            y: p[1],
            z: p[2],
            a: p[3],
            b: p[4],
            c: p[5],
        };
        Json {
            units: if r.inch { "in" } else { "mm" },
            counts: Counts {
                rapid: r.rapids,
                feed: r.feeds,
                arc: r.arcs,
                dwell: r.dwells,
                tool_change: r.tool_changes,
                m_code: r.m_codes,
                comment: r.comments,
            },
            length: Lengths {
                rapid: r.rapid_length,
                feed: r.feed_length,
                arc: r.arc_length,
                untimed: r.untimed_length,
            },
            extents: r.bounds.map(|b| Extents {
                min: axes(&b.min),
                max: axes(&b.max),
            }),
            time: Time {
                total_s: r.total_seconds,
                rapid_s: r.rapid_seconds,
                feed_s: r.feed_seconds,
                dwell_s: r.dwell_seconds,
                rapid_rate_mm_min: r.rapid_rate,
                untimed_feeds: r.untimed_feeds,
            },
            stock: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fmsvm_canon::Canon;
    use fmsvm_emit::stats::Stats;

    fn square() -> Report {
        let mut s = Stats::default();
        for op in [
            Canon::Tool(1.0),
            Canon::MCode(6.0),
            Canon::Rapid([0.0, 0.0, 5.0, 0.0, 0.0, 0.0]),
            Canon::FeedRate(100.0),
            Canon::Feed([10.0, 0.0, 5.0, 0.0, 0.0, 0.0]),
            Canon::Feed([10.0, 10.0, 5.0, 0.0, 0.0, 0.0]),
            Canon::Dwell(1.5),
            Canon::Comment("DONE"),
            Canon::MCode(30.0),
        ] {
            s.op(&op);
        }
        s.finish(6000.0)
    }

    #[test]
    fn stats_json_report_shape() {
        let mut out = Vec::new();
        report(&square(), None, true, &mut out).expect("write");
        let text = String::from_utf8(out).expect("utf-8");
        let v: serde_json::Value = serde_json::from_str(&text).expect("one JSON document");
        assert_eq!(v["units"], "mm");
        assert_eq!(v["counts"]["rapid"], 1);
        assert_eq!(v["counts"]["feed"], 2);
        assert_eq!(v["counts"]["arc"], 0);
        assert_eq!(v["counts"]["dwell"], 1);
        assert_eq!(v["counts"]["tool_change"], 1);
        assert_eq!(v["counts"]["m_code"], 2);
        assert_eq!(v["counts"]["comment"], 1);
        assert_eq!(v["length"]["rapid"], 5.0);
        assert_eq!(v["length"]["feed"], 20.0);
        assert_eq!(v["extents"]["min"]["z"], 0.0);
        assert_eq!(v["extents"]["max"]["x"], 10.0);
        assert_eq!(v["extents"]["max"]["y"], 10.0);
        assert_eq!(v["extents"]["max"]["z"], 5.0);
        // 20 mm at 100 mm/min = 12 s; 5 mm at 6000 mm/min = 0.05 s; 1.5 s dwell.
        let t = &v["time"];
        assert_eq!(t["feed_s"], 12.0);
        assert_eq!(t["dwell_s"], 1.5);
        assert_eq!(t["rapid_rate_mm_min"], 6000.0);
        let total = t["total_s"].as_f64().expect("number");
        assert!((total - 13.55).abs() < 1e-9, "{total}");
        assert_eq!(t["untimed_feeds"], 0);
        // Exactly these groups, in this order.
        let keys: Vec<&str> = v
            .as_object()
            .expect("object")
            .keys()
            .map(|k| k.as_str())
            .collect();
        let mut sorted = keys.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, ["counts", "extents", "length", "time", "units"]);
        // Nothing moved: extents is null.
        let mut out = Vec::new();
        report(&Stats::default().finish(1.0), None, true, &mut out).expect("write");
        let v: serde_json::Value = serde_json::from_slice(&out).expect("JSON");
        assert!(v["extents"].is_null());
    }

    #[test]
    fn stats_text_report() {
        let t = text(&square());
        assert!(t.contains("moves        1 rapid, 2 feed, 0 arc\n"), "{t}");
        assert!(
            t.contains("X 0.000 .. 10.000  Y 0.000 .. 10.000  Z 0.000 .. 5.000  mm"),
            "{t}"
        );
        assert!(
            t.contains(
                "time         0:00:14 (rapid 0.1 s at 6000 mm/min, feed 12.0 s, dwell 1.5 s)"
            ),
            "{t}"
        );
        assert!(t.contains("tool changes 1\n"), "{t}");
        assert!(!t.contains("not timed"));
    }
}
