//! `--offsets FILE`: work offsets, tool registers and reference positions from a TOML file, loaded into
//! the kernel's frames before the run. The format is in docs/offsets.md; every error names its line.
//!
//! ```toml
//! [work.G54]          # also G55 … G59, "G54.1 P1" … "G54.1 P48", external
//! X = 100.0
//! Z = -250.0
//! [tool.1]            # offset number 1 (H1, D1; a lathe's T0101)
//! length = 120.5      # geometry; length_wear, radius, radius_wear likewise
//! radius = 2.0        # a lathe tool's nose radius, with `tip = 3` its imaginary tool nose
//! [reference.G28]     # machine position of the first reference point; G30 P2 … G30 P4
//! Z = 0.0
//! ```

use std::collections::BTreeMap;

use fmsvm_kernel::frames::{Frames, TOOLS};
use serde::Deserialize;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    #[serde(default)]
    work: BTreeMap<Spanned<String>, Axes>,
    #[serde(default)]
    tool: BTreeMap<Spanned<String>, Tool>,
    #[serde(default)]
    reference: BTreeMap<Spanned<String>, Axes>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
struct Axes {
    X: Option<f64>,
    Y: Option<f64>,
    Z: Option<f64>,
    A: Option<f64>,
    B: Option<f64>,
    C: Option<f64>,
}

impl Axes {
    fn apply(&self, pose: &mut [f64; 6]) {
        for (slot, v) in pose
            .iter_mut()
            .zip([self.X, self.Y, self.Z, self.A, self.B, self.C])
        {
            if let Some(v) = v {
                *slot = v;
            }
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Tool {
    length: Option<f64>,
    length_wear: Option<f64>,
    radius: Option<f64>,
    radius_wear: Option<f64>,
    tip: Option<Spanned<i64>>,
    x: Option<f64>,
    z: Option<f64>,
    x_wear: Option<f64>,
    z_wear: Option<f64>,
    /// A milling cutter's shape for the stock: `flat`, `ball` or `bull` (with `corner`).
    #[serde(rename = "type")]
    shape: Option<Spanned<String>>,
    /// Its cutting diameter (default: twice the radius register).
    diameter: Option<f64>,
    /// A bull-nose cutter's corner radius.
    corner: Option<f64>,
    /// The flutes' length above the tip: the shank above them cuts nothing.
    flute_length: Option<f64>,
    /// The shank's diameter above the flutes (default: the cutting diameter).
    shank_diameter: Option<f64>,
    /// Whether the end cuts at its centre (default true).
    plunge: Option<bool>,
}

/// What an offsets file gives: the control's registers, and the milling cutters' shapes for the
/// stock (`[tool.N] type`, by tool number N).
pub struct Offsets {
    pub frames: Frames,
    pub cutters: BTreeMap<u32, fmsvm_stock::Cutter>,
}

/// Reads an offsets file; the error says `name:line:column: what`.
pub fn parse(name: &str, text: &str) -> Result<Frames, String> {
    parse_all(name, text).map(|o| o.frames)
}

/// Reads an offsets file with its cutters.
pub fn parse_all(name: &str, text: &str) -> Result<Offsets, String> {
    let file: File = crate::tomlfile::read(name, text)?;
    // An offset is a length: `nan` and `inf` (which TOML spells) are none.
    if let Ok(doc) = text.parse::<toml::Table>()
        && let Some(path) = non_finite(&toml::Value::Table(doc), String::new())
    {
        return Err(format!(
            "{name}: {path}: not a finite number of at most {MAX_OFFSET} (an offset is a length a control holds in eight digits)"
        ));
    }
    let at = |key: &Spanned<String>| crate::tomlfile::key_at(name, text, key);
    let mut frames = Frames::default();
    let mut seen: Vec<String> = Vec::new();
    for (key, axes) in &file.work {
        let k = key.get_ref().trim();
        let canonical = k
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ")
            .to_ascii_uppercase();
        if seen.contains(&canonical) {
            return Err(format!(
                "{}: [work.{k}]: this work offset is given twice",
                at(key)
            ));
        }
        seen.push(canonical);
        let (slot, target) = if k.eq_ignore_ascii_case("external") {
            (0, &mut frames.external)
        } else if let Some(n) = k
            .strip_prefix("G5")
            .filter(|d| d.len() == 1 && d.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|d| d.parse::<usize>().ok())
            .filter(|d| (4..=9).contains(d))
        {
            (n - 3, &mut frames.standard[n - 4])
        } else if let Some(p) = k
            .strip_prefix("G54.1")
            .map(str::trim)
            .and_then(|r| r.strip_prefix('P'))
            .filter(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|p| p.parse::<usize>().ok())
            .filter(|p| (1..=frames.extended.len()).contains(p))
        {
            (6 + p, &mut frames.extended[p - 1])
        } else {
            return Err(format!(
                "{}: [work.{k}]: a work offset is G54 to G59, \"G54.1 P1\" to \"G54.1 P48\" or external",
                at(key)
            ));
        };
        axes.apply(target);
        frames.work_set[slot] = true;
    }
    for (key, t) in &file.tool {
        let k = key.get_ref().trim();
        let n = k
            .parse::<usize>()
            .ok()
            .filter(|n| (1..=TOOLS).contains(n))
            .ok_or_else(|| {
                format!(
                    "{}: [tool.{k}]: a tool register is an offset number 1 to {TOOLS}",
                    at(key)
                )
            })?;
        let r = &mut frames.tools[n - 1];
        r.set = true;
        r.length_geometry = t.length.unwrap_or(0.0);
        r.length_wear = t.length_wear.unwrap_or(0.0);
        r.radius_geometry = t.radius.unwrap_or(0.0);
        r.radius_wear = t.radius_wear.unwrap_or(0.0);
        r.xz_geometry = [t.x.unwrap_or(0.0), t.z.unwrap_or(0.0)];
        r.xz_wear = [t.x_wear.unwrap_or(0.0), t.z_wear.unwrap_or(0.0)];
        if let Some(tip) = &t.tip {
            r.tip = u8::try_from(*tip.get_ref())
                .ok()
                .filter(|d| *d <= 9)
                .ok_or_else(|| {
                    format!(
                        "{}: [tool.{k}] tip = {}: the imaginary tool nose direction is 0 to 9",
                        crate::tomlfile::at(name, text, tip.span().start),
                        tip.get_ref()
                    )
                })?;
        }
    }
    for (key, axes) in &file.reference {
        let k = key.get_ref().trim();
        let n = match k {
            "G28" => 1,
            _ => k
                .strip_prefix("G30")
                .map(str::trim)
                .and_then(|r| r.strip_prefix('P'))
                .and_then(|p| p.parse::<usize>().ok())
                .filter(|p| (2..=4).contains(p))
                .ok_or_else(|| {
                    format!(
                        "{}: [reference.{k}]: a reference position is G28 or \"G30 P2\" to \"G30 P4\"",
                        at(key)
                    )
                })?,
        };
        axes.apply(&mut frames.reference[n - 1]);
    }
    let mut cutters = BTreeMap::new();
    for (key, t) in &file.tool {
        if let Some(c) = cutter(name, text, key, t)? {
            let n = key.get_ref().trim().parse::<u32>().unwrap_or(0);
            cutters.insert(n, c);
        }
    }
    Ok(Offsets { frames, cutters })
}

/// The milling cutter `[tool.N]` declares with `type`, if it does.
fn cutter(
    name: &str,
    text: &str,
    key: &Spanned<String>,
    t: &Tool,
) -> Result<Option<fmsvm_stock::Cutter>, String> {
    use fmsvm_stock::{Cutter, Shape};
    let k = key.get_ref().trim();
    let Some(shape) = &t.shape else {
        let stray = [t.diameter, t.corner, t.flute_length, t.shank_diameter]
            .iter()
            .any(Option::is_some)
            || t.plunge.is_some();
        if stray {
            return Err(format!(
                "{}: [tool.{k}]: a cutter's diameter, corner, flute_length, shank_diameter and plunge need its type (flat, ball or bull)",
                crate::tomlfile::key_at(name, text, key)
            ));
        }
        return Ok(None);
    };
    let at = crate::tomlfile::at(name, text, shape.span().start);
    let diameter = t.diameter.or(t.radius.map(|r| 2.0 * r)).unwrap_or(0.0);
    if diameter <= 0.0 {
        return Err(format!(
            "{at}: [tool.{k}] type = {:?}: give the cutter's diameter (or its radius register)",
            shape.get_ref()
        ));
    }
    let radius = diameter / 2.0;
    let kind = match shape.get_ref().as_str() {
        "flat" => Shape::Flat,
        "ball" => Shape::Ball,
        "bull" => match t.corner {
            Some(c) if c > 0.0 && c <= radius => Shape::Bull(c),
            _ => {
                return Err(format!(
                    "{at}: [tool.{k}] type = \"bull\": give its corner radius, above 0 and at most half the diameter"
                ));
            }
        },
        other => {
            return Err(format!(
                "{at}: [tool.{k}] type = {other:?}: a cutter is flat, ball or bull"
            ));
        }
    };
    let positive = |v: Option<f64>, what: &str| match v {
        Some(x) if x <= 0.0 => Err(format!("{at}: [tool.{k}] {what} = {x}: a length above 0")),
        _ => Ok(v),
    };
    let mut c = Cutter::new(kind, radius);
    c.flute_length = positive(t.flute_length, "flute_length")?;
    c.shank_radius = positive(t.shank_diameter, "shank_diameter")?.map(|d| d / 2.0);
    c.plunges = t.plunge.unwrap_or(true);
    Ok(Some(c))
}

/// The largest offset a control holds (Fanuc's eight digits at 0.001 mm: 99999.999).
const MAX_OFFSET: f64 = 99_999.999;

/// The key path of the first number that is not finite or is beyond `MAX_OFFSET`, if any.
fn non_finite(v: &toml::Value, path: String) -> Option<String> {
    match v {
        toml::Value::Float(f) if !f.is_finite() || f.abs() > MAX_OFFSET => Some(path),
        toml::Value::Integer(i) if (*i as f64).abs() > MAX_OFFSET => Some(path),
        toml::Value::Table(t) => t.iter().find_map(|(k, v)| {
            non_finite(
                v,
                if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                },
            )
        }),
        toml::Value::Array(a) => a.iter().find_map(|v| non_finite(v, path.clone())),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_section() {
        let f = parse(
            "o.toml",
            "[work.G55]\nX = 10.0\nZ = -5\n[work.\"G54.1 P48\"]\nY = 2.5\n[work.external]\nZ = 1.0\n\
             [tool.7]\nlength = 100.0\nradius = 2.0\nradius_wear = -0.01\n[reference.\"G30 P2\"]\nZ = -10.0\n",
        )
        .expect("parses");
        assert_eq!(f.standard[1][..3], [10.0, 0.0, -5.0]);
        assert_eq!(f.extended[47][1], 2.5);
        assert_eq!(f.external[2], 1.0);
        assert_eq!(f.tools[6].length(), 100.0);
        assert!((f.tools[6].radius() - 1.99).abs() < 1e-12);
        assert_eq!(f.reference[1][2], -10.0);
    }

    #[test]
    fn errors_name_their_line() {
        let e = parse("o.toml", "[work.G54]\nX = 1.0\n\n[work.G60]\nX = 2.0\n").unwrap_err();
        // Every TOML file's errors are `file:line:column` (the key `G60` starts in column 7).
        assert!(e.starts_with("o.toml:4:7: [work.G60]"), "{e}");
        let e = parse("o.toml", "[tool.1]\nlength = 1.0\nlenght = 2.0\n").unwrap_err();
        assert!(e.starts_with("o.toml:3:") && e.contains("lenght"), "{e}");
        let e = parse("o.toml", "[work.G54]\nX = \"ten\"\n").unwrap_err();
        assert!(e.starts_with("o.toml:2:"), "{e}");
        let e = parse("o.toml", "[tool.1000]\nlength = 1.0\n").unwrap_err();
        assert!(e.starts_with("o.toml:1:"), "{e}");
        let e = parse("o.toml", "[tool.2]\nx = nan\n").unwrap_err();
        assert!(e.contains("tool.2.x: not a finite number"), "{e}");
        let e = parse("o.toml", "[work.G54]\nX = -inf\n").unwrap_err();
        assert!(e.contains("work.G54.X: not a finite number"), "{e}");
        let e = parse("o.toml", "[tool.2]\nradius = 0.8\ntip = 12\n").unwrap_err();
        assert!(e.starts_with("o.toml:3:7: [tool.2] tip = 12"), "{e}");
        let f = parse("o.toml", "[tool.2]\nradius = 0.8\ntip = 3\n").expect("parses");
        assert_eq!((f.tools[1].tip, f.tools[1].radius()), (3, 0.8));
    }
}
