//! Mutations of an input file's bytes: operators that hit the parsers (truncation, stray bytes, wrong
//! types, duplicated or missing keys and tables) and the physics (extreme and rescaled numbers, names
//! swapped for others of the file, joint and force types swapped, bodies duplicated under new names).
//! Each returns a one-line description of what it did, for the report of a failing case.

use super::rng::Rng;

/// The syntax of the file being mutated: which lines are section headers and which values are worth
/// swapping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Syntax {
    /// Model, FE model and study files: `[table]` and `[[array]]` headers, `key = value` lines.
    Toml,
    /// Abaqus/CalculiX decks: `*KEYWORD, PARAM=value` lines and their data lines.
    Inp,
    /// Result files: a header row and rows of numbers.
    Csv,
}

/// Applies one to four mutations (fewer more often) to `text` and says what each did. Half of the
/// time only values change (numbers, names, array lengths, whole tables duplicated under new names):
/// the file still parses more often and the mutation reaches the physics.
pub fn mutate(rng: &mut Rng, text: &mut Vec<u8>, syntax: Syntax) -> Vec<String> {
    let operators: Vec<(u32, Operator)> = if rng.chance(0.5) {
        OPERATORS.to_vec()
    } else {
        OPERATORS.iter().copied().filter(|(_, op)| VALUE_OPERATORS.contains(op)).collect()
    };
    let mut done = Vec::new();
    loop {
        if let Some(d) = (0..20).find_map(|_| mutate_once(rng, text, syntax, &operators)) {
            done.push(d);
        }
        if done.len() >= 4 || !rng.chance(0.4) {
            return done;
        }
    }
}

type Operator = fn(&mut Rng, &mut Vec<u8>, Syntax) -> Option<String>;

/// The operators with their weights; an operator that does not apply (no number in the text, no
/// section) returns `None` and another is drawn.
const OPERATORS: &[(u32, Operator)] = &[
    (14, extreme_number),
    (8, rescaled_number),
    (10, swapped_string),
    (4, renamed_key),
    (5, flipped_type),
    (5, resized_array),
    (4, deleted_line),
    (3, duplicated_line),
    (3, swapped_lines),
    (4, deleted_section),
    (5, duplicated_section),
    (2, swapped_sections),
    (3, truncated),
    (3, inserted_bytes),
    (1, deleted_bytes),
    (2, resized_row),
];

/// The operators that change values only.
const VALUE_OPERATORS: &[Operator] = &[extreme_number, rescaled_number, swapped_string, resized_array, duplicated_section];

fn mutate_once(rng: &mut Rng, text: &mut Vec<u8>, syntax: Syntax, operators: &[(u32, Operator)]) -> Option<String> {
    let total: u32 = operators.iter().map(|(w, _)| w).sum();
    let mut k = rng.below(total as usize) as u32;
    for (w, op) in operators {
        if k < *w {
            return op(rng, text, syntax);
        }
        k -= w;
    }
    unreachable!()
}

// ---- numbers ----

const TOML_EXTREMES: &[&str] = &[
    "0", "-0", "0.0", "-0.0", "-1", "1", "2", "0.5", "1e-300", "1e300", "-1e300", "1.7976931348623157e308",
    "-1.7976931348623157e308", "5e-324", "nan", "-nan", "inf", "+inf", "-inf", "9223372036854775807",
    "-9223372036854775808", "18446744073709551616", "1e12", "1e-12", "1000000", "100000000",
];
const INP_EXTREMES: &[&str] = &[
    "0", "-0.", "-1", "1", "2", "1.E-300", "1e300", "1.7976931348623157E308", "1.D308", "1e999", "5e-324", "NaN",
    "nan", "Inf", "-inf", "9999999999", "2147483648", "4294967297", "1e12", "1e-12", "1000000", "0.5", "3",
];
const CSV_EXTREMES: &[&str] =
    &["NaN", "nan", "inf", "-inf", "1e308", "-1.7976931348623157e308", "", "0", "-0", "1e-320", "x", "1,2", "1e400"];

fn is_word_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b == b'.'
}

/// The byte ranges of the number literals in `text` (with a leading sign when there is one), including
/// those inside strings (expressions, mode sets) and data lines.
fn numbers(text: &[u8]) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut i = 0;
    while i < text.len() {
        let starts = text[i].is_ascii_digit() || (text[i] == b'.' && text.get(i + 1).is_some_and(u8::is_ascii_digit));
        if !starts || (i > 0 && is_word_byte(text[i - 1])) {
            i += 1;
            continue;
        }
        let mut start = i;
        if i > 0 && (text[i - 1] == b'-' || text[i - 1] == b'+') && (i < 2 || !is_word_byte(text[i - 2])) {
            start = i - 1;
        }
        let mut j = i;
        while j < text.len() && (text[j].is_ascii_digit() || text[j] == b'.' || text[j] == b'_') {
            j += 1;
        }
        if j < text.len() && matches!(text[j], b'e' | b'E' | b'd' | b'D') {
            let mut k = j + 1;
            if k < text.len() && (text[k] == b'-' || text[k] == b'+') {
                k += 1;
            }
            if k < text.len() && text[k].is_ascii_digit() {
                while k < text.len() && text[k].is_ascii_digit() {
                    k += 1;
                }
                j = k;
            }
        }
        spans.push((start, j));
        i = j;
    }
    spans
}

fn replace(text: &mut Vec<u8>, (start, end): (usize, usize), with: &[u8]) {
    text.splice(start..end, with.iter().copied());
}

fn show(bytes: &[u8]) -> String {
    let s = String::from_utf8_lossy(bytes);
    let s: String = s.chars().take(60).collect();
    format!("{s:?}")
}

/// The 1-based line of byte `at`.
fn line_of(text: &[u8], at: usize) -> usize {
    1 + text[..at.min(text.len())].iter().filter(|&&b| b == b'\n').count()
}

fn extreme_number(rng: &mut Rng, text: &mut Vec<u8>, syntax: Syntax) -> Option<String> {
    let spans = numbers(text);
    if spans.is_empty() {
        return None;
    }
    let span = *rng.pick(&spans);
    let with = rng.pick(match syntax {
        Syntax::Toml => TOML_EXTREMES,
        Syntax::Inp => INP_EXTREMES,
        Syntax::Csv => CSV_EXTREMES,
    });
    let d = format!("line {}: number {} -> {with:?}", line_of(text, span.0), show(&text[span.0..span.1]));
    replace(text, span, with.as_bytes());
    Some(d)
}

fn rescaled_number(rng: &mut Rng, text: &mut Vec<u8>, _: Syntax) -> Option<String> {
    let spans = numbers(text);
    if spans.is_empty() {
        return None;
    }
    let span = *rng.pick(&spans);
    let old = String::from_utf8_lossy(&text[span.0..span.1]).replace(['d', 'D'], "e").replace('_', "");
    let x: f64 = old.parse().ok()?;
    let factor = match rng.below(4) {
        0 => -1.0,
        1 => 10f64.powi(rng.between(1, 20) as i32),
        2 => 10f64.powi(-(rng.between(1, 20) as i32)),
        _ => rng.range(-3.0, 3.0),
    };
    let new = if x == 0.0 { format!("{factor:e}") } else { format!("{:e}", x * factor) };
    let d = format!("line {}: number {old} -> {new}", line_of(text, span.0));
    replace(text, span, new.as_bytes());
    Some(d)
}

// ---- strings and names ----

/// Names and words a file may hold, to put where another stands: types of joints, forces, measures,
/// outputs, shapes, supports, mode sets, integrators, element types and expressions that are
/// undefined somewhere.
const WORDS: &[&str] = &[
    "ground", "revolute", "spherical", "universal", "cylindrical", "translational", "fixed", "planar", "distance",
    "dot-1", "dot-2", "point-on-line", "point-in-plane", "angle", "displacement", "translational_spring_damper",
    "rotational_spring_damper", "force", "torque", "global", "body", "marker", "joint_angle", "joint_rate",
    "joint_displacement", "joint_velocity", "distance_rate", "position", "velocity", "speed", "marker_position",
    "marker_velocity", "marker_acceleration", "marker_angular_velocity", "joint_reaction", "measure", "energy",
    "constraint_residual", "modal_coordinates", "node_position", "node_velocity", "node_acceleration",
    "node_deformation", "strain_energy", "x", "y", "z", "rx", "ry", "rz", "all", "translations", "rotations",
    "rectangle", "circle", "tube", "quadrilateral", "triangle", "lumped", "consistent", "raw", "orthonormal",
    "held", "free", "static", "bdf", "adams", "gen-alpha", "bdf:1", "bdf:9", "rigid", "0N", "1N", "9N", "99N",
    "1S", "9S", "4N5S", "N", "NS", "t", "PI", "1/0", "0/0", "-1", "sqrt(-1)", "ln(0)", "acos(2)", "exp(1000)",
    "1e308*10", "t^1000", "1/t", "tan(PI/2)", "max(t)", "2 PI", "((t)", "t*1e308", "B31", "B33", "S3", "S4", "S4R",
    "MASS", "ROTARYI", "C3D8", "RECT", "CIRC", "PIPE", "BOX", "GENERAL", "ENCASTRE", "PINNED", "XSYMM", "",
    "nowhere", "ghost_7", "ümlaut", "π", "a.b.c", "door.node11.position.x", "energy.total",
];

/// The byte ranges of the insides of `"…"` strings (Toml), of `PARAM=value` values (Inp), and of the
/// header's column names (Csv).
fn strings(text: &[u8], syntax: Syntax) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    match syntax {
        Syntax::Toml => {
            let mut open: Option<usize> = None;
            let mut i = 0;
            while i < text.len() {
                match (text[i], open) {
                    (b'\\', Some(_)) => i += 1,
                    (b'"', None) => open = Some(i + 1),
                    (b'"', Some(s)) => {
                        spans.push((s, i));
                        open = None;
                    }
                    (b'\n', _) => open = None,
                    (b'#', None) => {
                        while i < text.len() && text[i] != b'\n' {
                            i += 1;
                        }
                        continue;
                    }
                    _ => {}
                }
                i += 1;
            }
        }
        Syntax::Inp => {
            for (start, line) in lines(text) {
                if !line.starts_with(b"*") || line.starts_with(b"**") {
                    continue;
                }
                for (k, &b) in line.iter().enumerate() {
                    if b == b'=' {
                        let end = line[k + 1..].iter().position(|&c| c == b',').map_or(line.len(), |p| k + 1 + p);
                        spans.push((start + k + 1, start + end));
                    }
                }
            }
        }
        Syntax::Csv => {
            let header_end = text.iter().position(|&b| b == b'\n').unwrap_or(text.len());
            let mut s = 0;
            for k in 0..=header_end {
                if k == header_end || text[k] == b',' {
                    spans.push((s, k));
                    s = k + 1;
                }
            }
        }
    }
    spans
}

fn swapped_string(rng: &mut Rng, text: &mut Vec<u8>, syntax: Syntax) -> Option<String> {
    let spans = strings(text, syntax);
    if spans.is_empty() {
        return None;
    }
    let span = *rng.pick(&spans);
    let with: Vec<u8> = match rng.below(6) {
        0..=2 => {
            let other = *rng.pick(&spans);
            text[other.0..other.1].to_vec()
        }
        3 => "x".repeat(rng.between(100, 5000)).into_bytes(),
        _ => rng.pick(WORDS).as_bytes().to_vec(),
    };
    let d = format!("line {}: string {} -> {}", line_of(text, span.0), show(&text[span.0..span.1]), show(&with));
    replace(text, span, &with);
    Some(d)
}

const KEYS: &[&str] = &[
    "name", "type", "mass", "inertia", "position", "orientation", "velocity", "angular_velocity", "origin", "body",
    "node", "i", "j", "joint", "function", "stiffness", "damping", "free_length", "actuator", "components", "frame",
    "marker", "measure", "length", "axis_i", "axis_j", "z_axis", "x_axis", "t_end", "output_step", "rtol", "atol",
    "integrator", "max_order", "gravity", "fe_model", "modes", "set", "basis", "E", "nu", "rho", "section",
    "material", "elements", "from", "to", "at", "dofs", "force", "torque", "thickness", "width", "height", "model",
    "integrators", "plot", "parameters", "mesh", "rotary_inertia", "modal_coordinates", "modal_assembly", "unknown",
];

/// A `key = value` line's key: its byte range.
fn key_of(line: &[u8]) -> Option<(usize, usize)> {
    let start = line.iter().position(|b| !b.is_ascii_whitespace())?;
    let len = line[start..].iter().position(|&b| !(b.is_ascii_alphanumeric() || b == b'_' || b == b'-'))?;
    let rest = &line[start + len..];
    let eq = rest.iter().position(|b| !b.is_ascii_whitespace())?;
    (len > 0 && rest[eq] == b'=').then_some((start, start + len))
}

/// The byte ranges that `part` finds in the lines of a TOML text (none in other syntaxes).
fn toml_spans(text: &[u8], syntax: Syntax, part: fn(&[u8]) -> Option<(usize, usize)>) -> Vec<(usize, usize)> {
    if syntax != Syntax::Toml {
        return Vec::new();
    }
    lines(text).into_iter().filter_map(|(s, l)| part(l).map(|(a, b)| (s + a, s + b))).collect()
}

fn renamed_key(rng: &mut Rng, text: &mut Vec<u8>, syntax: Syntax) -> Option<String> {
    let keys = toml_spans(text, syntax, key_of);
    if keys.is_empty() {
        return None;
    }
    let span = *rng.pick(&keys);
    let with = if rng.chance(0.5) {
        let other = *rng.pick(&keys);
        text[other.0..other.1].to_vec()
    } else {
        rng.pick(KEYS).as_bytes().to_vec()
    };
    let d = format!("line {}: key {} -> {}", line_of(text, span.0), show(&text[span.0..span.1]), show(&with));
    replace(text, span, &with);
    Some(d)
}

/// The value of a `key = value` line, without a trailing comment.
fn value_of(line: &[u8]) -> Option<(usize, usize)> {
    let (_, key_end) = key_of(line)?;
    let eq = key_end + line[key_end..].iter().position(|&b| b == b'=')?;
    let start = eq + 1 + line[eq + 1..].iter().position(|b| !b.is_ascii_whitespace())?;
    let mut in_string = false;
    let mut end = line.len();
    for (k, &b) in line.iter().enumerate().skip(start) {
        match b {
            b'"' => in_string = !in_string,
            b'#' if !in_string => {
                end = k;
                break;
            }
            _ => {}
        }
    }
    while end > start && line[end - 1].is_ascii_whitespace() {
        end -= 1;
    }
    (end > start).then_some((start, end))
}

fn flipped_type(rng: &mut Rng, text: &mut Vec<u8>, syntax: Syntax) -> Option<String> {
    let values = toml_spans(text, syntax, value_of);
    if values.is_empty() {
        return None;
    }
    let span = *rng.pick(&values);
    let old = text[span.0..span.1].to_vec();
    let inner = String::from_utf8_lossy(&old).into_owned();
    let unquoted = inner.trim_start_matches('"').trim_end_matches('"');
    let new = match old[0] {
        b'"' => rng.pick(&["1", "[\"a\"]", "true", "{}", unquoted]).to_string(),
        b'[' => {
            let elements = split_elements(&inner);
            let first = elements.first().cloned().unwrap_or_default();
            rng.pick(&[first, format!("{inner:?}"), format!("[{inner}]"), "[]".into(), "{}".into(), "0".into()]).clone()
        }
        b'{' => rng.pick(&["[]", "1", "\"x\"", "{}"]).to_string(),
        b't' | b'f' => rng.pick(&["1", "\"true\""]).to_string(),
        _ => rng.pick(&[format!("\"{inner}\""), format!("[{inner}]"), "true".into(), "{}".into(), "[]".into()]).clone(),
    };
    let d = format!("line {}: value {} -> {}", line_of(text, span.0), show(&old), show(new.as_bytes()));
    replace(text, span, new.as_bytes());
    Some(d)
}

/// The top-level comma-separated elements of an array written `[a, b, …]`.
fn split_elements(array: &str) -> Vec<String> {
    let body = array.trim().strip_prefix('[').and_then(|s| s.strip_suffix(']')).unwrap_or(array);
    let (mut depth, mut in_string, mut start) = (0i32, false, 0);
    let mut out = Vec::new();
    for (k, c) in body.char_indices() {
        match c {
            '"' => in_string = !in_string,
            '[' | '{' if !in_string => depth += 1,
            ']' | '}' if !in_string => depth -= 1,
            ',' if !in_string && depth == 0 => {
                out.push(body[start..k].trim().to_string());
                start = k + 1;
            }
            _ => {}
        }
    }
    if !body[start..].trim().is_empty() {
        out.push(body[start..].trim().to_string());
    }
    out
}

fn resized_array(rng: &mut Rng, text: &mut Vec<u8>, syntax: Syntax) -> Option<String> {
    let arrays: Vec<(usize, usize)> =
        toml_spans(text, syntax, value_of).into_iter().filter(|&(a, b)| text[a] == b'[' && text[b - 1] == b']').collect();
    if arrays.is_empty() {
        return None;
    }
    let span = *rng.pick(&arrays);
    let old = String::from_utf8_lossy(&text[span.0..span.1]).into_owned();
    let mut elements = split_elements(&old);
    match rng.below(4) {
        0 if !elements.is_empty() => {
            elements.pop();
        }
        1 => elements.clear(),
        2 => {
            let extra = elements.last().cloned().unwrap_or_else(|| "1".into());
            let n = if rng.chance(0.2) { rng.between(10, 2000) } else { 1 };
            elements.extend(std::iter::repeat_n(extra, n));
        }
        _ => {
            let extra = elements.last().cloned().unwrap_or_else(|| "0".into());
            elements.push(extra);
        }
    }
    let new = format!("[{}]", elements.join(", "));
    let d = format!("line {}: array {} -> {} elements", line_of(text, span.0), show(old.as_bytes()), elements.len());
    replace(text, span, new.as_bytes());
    Some(d)
}

// ---- lines and sections ----

/// Each line's start and bytes (without its `\n`).
fn lines(text: &[u8]) -> Vec<(usize, &[u8])> {
    let mut out = Vec::new();
    let mut start = 0;
    for (k, &b) in text.iter().enumerate() {
        if b == b'\n' {
            out.push((start, &text[start..k]));
            start = k + 1;
        }
    }
    if start < text.len() {
        out.push((start, &text[start..]));
    }
    out
}

/// The byte ranges of whole lines (with their `\n`), by line index.
fn line_ranges(text: &[u8]) -> Vec<(usize, usize)> {
    lines(text).into_iter().map(|(s, l)| (s, (s + l.len() + 1).min(text.len()))).collect()
}

fn deleted_line(rng: &mut Rng, text: &mut Vec<u8>, _: Syntax) -> Option<String> {
    let ranges = line_ranges(text);
    if ranges.is_empty() {
        return None;
    }
    let k = rng.below(ranges.len());
    let d = format!("line {}: deleted {}", k + 1, show(&text[ranges[k].0..ranges[k].1]));
    replace(text, ranges[k], b"");
    Some(d)
}

fn duplicated_line(rng: &mut Rng, text: &mut Vec<u8>, _: Syntax) -> Option<String> {
    let ranges = line_ranges(text);
    if ranges.is_empty() {
        return None;
    }
    let k = rng.below(ranges.len());
    let mut line = text[ranges[k].0..ranges[k].1].to_vec();
    if line.last() != Some(&b'\n') {
        line.insert(0, b'\n');
    }
    let d = format!("line {}: duplicated {}", k + 1, show(&line));
    text.splice(ranges[k].1..ranges[k].1, line);
    Some(d)
}

/// Two different indices below `n`, in order.
fn two_of(rng: &mut Rng, n: usize) -> Option<(usize, usize)> {
    if n < 2 {
        return None;
    }
    let (a, b) = (rng.below(n), rng.below(n));
    (a != b).then(|| (a.min(b), a.max(b)))
}

fn swapped_lines(rng: &mut Rng, text: &mut Vec<u8>, _: Syntax) -> Option<String> {
    let ranges = line_ranges(text);
    let (a, b) = two_of(rng, ranges.len())?;
    let first = line_text(text, ranges[a]);
    let second = line_text(text, ranges[b]);
    let d = format!("lines {} and {} swapped", a + 1, b + 1);
    replace(text, (ranges[b].0, ranges[b].0 + second.len()), &first);
    replace(text, (ranges[a].0, ranges[a].0 + first.len()), &second);
    Some(d)
}

/// A line's bytes without its `\n`.
fn line_text(text: &[u8], (start, end): (usize, usize)) -> Vec<u8> {
    let line = &text[start..end];
    line.strip_suffix(b"\n").unwrap_or(line).to_vec()
}

fn is_header(line: &[u8], syntax: Syntax) -> bool {
    let t = line.trim_ascii_start();
    match syntax {
        Syntax::Toml => t.starts_with(b"["),
        Syntax::Inp => t.starts_with(b"*") && !t.starts_with(b"**"),
        Syntax::Csv => false,
    }
}

/// The byte ranges of the sections: a header line and the lines up to the next header.
fn sections(text: &[u8], syntax: Syntax) -> Vec<(usize, usize)> {
    let starts: Vec<usize> = lines(text).into_iter().filter(|(_, l)| is_header(l, syntax)).map(|(s, _)| s).collect();
    starts.iter().enumerate().map(|(k, &s)| (s, starts.get(k + 1).copied().unwrap_or(text.len()))).collect()
}

fn section_title(text: &[u8], (start, _): (usize, usize)) -> String {
    let end = text[start..].iter().position(|&b| b == b'\n').map_or(text.len(), |p| start + p);
    show(&text[start..end])
}

fn deleted_section(rng: &mut Rng, text: &mut Vec<u8>, syntax: Syntax) -> Option<String> {
    let all = sections(text, syntax);
    if all.is_empty() {
        return None;
    }
    let s = *rng.pick(&all);
    let d = format!("line {}: deleted section {}", line_of(text, s.0), section_title(text, s));
    replace(text, s, b"");
    Some(d)
}

/// Duplicates a section; a duplicated `[[table]]` keeps its names half of the time (a duplicate-name
/// error) and otherwise takes new ones (another body, joint or force just like the first).
fn duplicated_section(rng: &mut Rng, text: &mut Vec<u8>, syntax: Syntax) -> Option<String> {
    let all = sections(text, syntax);
    if all.is_empty() {
        return None;
    }
    let s = *rng.pick(&all);
    let mut copy = text[s.0..s.1].to_vec();
    if copy.last() != Some(&b'\n') {
        copy.push(b'\n');
    }
    let renamed = syntax == Syntax::Toml && rng.chance(0.5);
    if renamed {
        let mut out = Vec::new();
        for (_, line) in lines(&copy) {
            out.extend_from_slice(line);
            if key_of(line).is_some_and(|(a, b)| &line[a..b] == b"name") {
                if let Some(q) = out.iter().rposition(|&b| b == b'"') {
                    out.splice(q..q, b"_copy".iter().copied());
                }
            }
            out.push(b'\n');
        }
        copy = out;
    }
    let d = format!(
        "line {}: duplicated section {}{}",
        line_of(text, s.0),
        section_title(text, s),
        if renamed { " with its names renamed" } else { "" }
    );
    let mut at = s.1;
    if at == text.len() && !text.ends_with(b"\n") {
        text.push(b'\n');
        at = text.len();
    }
    text.splice(at..at, copy);
    Some(d)
}

fn swapped_sections(rng: &mut Rng, text: &mut Vec<u8>, syntax: Syntax) -> Option<String> {
    let all = sections(text, syntax);
    let (a, b) = two_of(rng, all.len())?;
    let (first, second) = (all[a], all[b]);
    let mut one = text[first.0..first.1].to_vec();
    let mut two = text[second.0..second.1].to_vec();
    for s in [&mut one, &mut two] {
        if s.last() != Some(&b'\n') {
            s.push(b'\n');
        }
    }
    let d = format!("sections {} and {} swapped", section_title(text, first), section_title(text, second));
    replace(text, second, &one);
    replace(text, first, &two);
    Some(d)
}

// ---- bytes ----

fn truncated(rng: &mut Rng, text: &mut Vec<u8>, _: Syntax) -> Option<String> {
    if text.is_empty() {
        return None;
    }
    let at = rng.below(text.len());
    text.truncate(at);
    Some(format!("truncated at byte {at} (line {})", line_of(text, at)))
}

const STRAY: &[&[u8]] = &[
    b"\0", b"\r", b"\n", b"\r\n", b"\"", b"'", b"[", b"]", b"[[", b"=", b",", b"{", b"}", b"#", b"\\", b"\t", b"*",
    b"**", b"\xff", b"\xc3", b"\xe2\x80", "é".as_bytes(), "π".as_bytes(), "\u{feff}".as_bytes(), "\u{202e}".as_bytes(),
    "😀".as_bytes(), b"\x7f", b"\x1b[2J", b"-", b".", b"e", b" ", b"\"\"\"", b"'''",
];

fn inserted_bytes(rng: &mut Rng, text: &mut Vec<u8>, _: Syntax) -> Option<String> {
    let at = rng.below(text.len() + 1);
    let bytes: Vec<u8> = if rng.chance(0.3) {
        (0..rng.between(1, 8)).map(|_| rng.next_u64() as u8).collect()
    } else {
        rng.pick(STRAY).to_vec()
    };
    let d = format!("line {}: inserted {bytes:?} at byte {at}", line_of(text, at));
    text.splice(at..at, bytes);
    Some(d)
}

fn deleted_bytes(rng: &mut Rng, text: &mut Vec<u8>, _: Syntax) -> Option<String> {
    if text.is_empty() {
        return None;
    }
    let at = rng.below(text.len());
    let end = (at + rng.between(1, 20)).min(text.len());
    let d = format!("line {}: deleted bytes {}", line_of(text, at), show(&text[at..end]));
    replace(text, (at, end), b"");
    Some(d)
}

/// Drops or adds a field of a CSV row or an `.inp` data line.
fn resized_row(rng: &mut Rng, text: &mut Vec<u8>, syntax: Syntax) -> Option<String> {
    if syntax == Syntax::Toml {
        return None;
    }
    let rows: Vec<(usize, usize)> = line_ranges(text)
        .into_iter()
        .filter(|&(a, b)| text[a..b].contains(&b',') && !is_header(&text[a..b], syntax) && !text[a..].starts_with(b"**"))
        .collect();
    if rows.is_empty() {
        return None;
    }
    let r = *rng.pick(&rows);
    let line = line_text(text, r);
    let new: Vec<u8> = if rng.chance(0.5) {
        let cut = line.iter().rposition(|&b| b == b',').unwrap_or(0);
        line[..cut].to_vec()
    } else {
        [&line[..], b",", *rng.pick(&[&b"1"[..], b"", b"0", b"1e300"])].concat()
    };
    let d = format!("line {}: row {} -> {}", line_of(text, r.0), show(&line), show(&new));
    replace(text, (r.0, r.0 + line.len()), &new);
    Some(d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_found_with_their_signs_and_exponents_but_not_inside_names() {
        // The 5 of 4N5S follows a letter, as the 2 of b2 does: only the 4 counts.
        let text = b"a = -9.81e-3\nb2 = [1, +2.5]\nf = \"4N5S\"\nx = 1.5D3";
        let found: Vec<String> = numbers(text).iter().map(|&(a, b)| String::from_utf8_lossy(&text[a..b]).into()).collect();
        assert_eq!(found, ["-9.81e-3", "1", "+2.5", "4", "1.5D3"]);
    }

    #[test]
    fn strings_keys_values_and_sections_are_found() {
        let text = b"[[body]] # one\nname = \"a\" # \"not this\"\nv = [1, [2, 3], \"x,y\"]\n[model]\n";
        let s: Vec<&[u8]> = strings(text, Syntax::Toml).iter().map(|&(a, b)| &text[a..b]).collect();
        assert_eq!(s, [&b"a"[..], b"x,y"]);
        assert_eq!(split_elements("[1, [2, 3], \"x,y\"]"), ["1", "[2, 3]", "\"x,y\""]);
        assert_eq!(value_of(b"name = \"a\" # c").map(|(a, b)| &b"name = \"a\" # c"[a..b]), Some(&b"\"a\""[..]));
        assert_eq!(sections(text, Syntax::Toml).len(), 2);
    }

    #[test]
    fn every_operator_keeps_working_on_its_own_output() {
        let mut rng = Rng::for_case(3, 3);
        for syntax in [Syntax::Toml, Syntax::Inp, Syntax::Csv] {
            let mut text = b"[a]\nk = [1, 2]\nname = \"x\"\n*NODE, NSET=N\n1, 0., 0., 0.\nt,x\n0,1\n".to_vec();
            for _ in 0..2000 {
                mutate(&mut rng, &mut text, syntax);
                if text.len() > 100_000 || text.is_empty() {
                    text = b"[a]\nk = 1\n".to_vec();
                }
            }
        }
    }
}
