//! Reading YAML (and JSON) with the project's limits, and the parser's errors as messages:
//! the problem in words, the dotted key path at fault, and what was found there.

use std::fmt::Write;

use serde::de::{self, Deserialize, Deserializer, Visitor};

use crate::math::Real;

/// A number as an input file writes it: a plain YAML scalar or a JSON number, never a
/// quoted string. serde-saphyr reads a quoted `'5'` or `"5"` into an `f64` as it reads `5`;
/// `docs/formats.md` refuses a value of the wrong type, and a quoted number is a string.
/// Read through `deserialize_any`, so the parser says which it found.
///
/// # Examples
///
/// ```
/// use homospline_geom::yaml::{Number, from_yaml};
///
/// let ok: [Number; 2] = from_yaml("[5, 2.5e1]").unwrap();
/// assert_eq!(ok, [Number(5.0), Number(25.0)]);
/// let quoted = from_yaml::<[Number; 2]>("['5', 30]").unwrap_err();
/// assert!(quoted.to_string().contains("without quotes), not the string '5'"));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Number(pub Real);

/// A whole number `>= 0` as an input file writes it (a version): plain, never quoted; see
/// [`Number`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Whole(pub u32);

/// What a [`Number`] is, in an error.
const A_NUMBER: &str = "a number (such as 2, -1.5 or 3e-2, without quotes)";
/// What a [`Whole`] is, in an error.
const A_WHOLE: &str = "a whole number >= 0 (without quotes)";

/// The problem of a string (quoted or not) where a number belongs. The parser hands over as
/// strings the plain scalars that look like numbers but that this reader refuses: a hex or
/// octal number too large for 64 bits, and the spellings YAML 1.1 and 1.2 read differently
/// (underscores between digits, a leading zero); each is named as what it is.
fn quoted<E: de::Error>(v: &str, what: &str) -> E {
    let bare = v.trim_start_matches(['+', '-']).to_ascii_lowercase();
    if ["nan", "inf", "infinity"].contains(&bare.as_str()) {
        // JSON's and other languages' spellings of what is no finite number.
        return E::custom(format!("expected {what}, not '{v}': it must be finite"));
    }
    let digits = |s: &str, radix: u32| !s.is_empty() && s.chars().all(|c| c.is_digit(radix));
    let radix = [("0x", 16), ("0o", 8)]
        .into_iter()
        .find_map(|(prefix, radix)| Some((bare.strip_prefix(prefix)?, radix)))
        .filter(|&(rest, radix)| digits(rest, radix));
    if let Some((rest, radix)) = radix
        && u64::from_str_radix(rest, radix).is_err()
    {
        return E::custom(format!(
            "expected {what}, not '{v}': too large for a whole number (at most 2^64 - 1)"
        ));
    }
    let numeric = bare.starts_with(|c: char| c.is_ascii_digit())
        && bare
            .chars()
            .all(|c| c.is_ascii_digit() || "_.e+-".contains(c));
    if numeric && bare.contains('_') {
        return E::custom(format!(
            "expected {what}, not '{v}': YAML 1.1 reads digits with underscores as a number \
             and YAML 1.2 as a string; write it without underscores"
        ));
    }
    if bare.len() > 1 && bare.starts_with('0') && digits(&bare, 10) {
        return E::custom(format!(
            "expected {what}, not '{v}': YAML 1.1 reads a leading zero as octal and YAML 1.2 \
             as decimal; write it without the leading zero"
        ));
    }
    E::custom(format!("expected {what}, not the string '{v}'"))
}

impl<'de> Deserialize<'de> for Number {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Number;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(A_NUMBER)
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Number, E> {
                Ok(Number(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Number, E> {
                Ok(Number(v as Real))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Number, E> {
                Ok(Number(v as Real))
            }
            fn visit_i128<E: de::Error>(self, v: i128) -> Result<Number, E> {
                Ok(Number(v as Real))
            }
            fn visit_u128<E: de::Error>(self, v: u128) -> Result<Number, E> {
                Ok(Number(v as Real))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Number, E> {
                Err(quoted(v, A_NUMBER))
            }
            fn visit_bool<E: de::Error>(self, _: bool) -> Result<Number, E> {
                Err(E::custom(format!("expected {A_NUMBER}")))
            }
            fn visit_unit<E: de::Error>(self) -> Result<Number, E> {
                Err(E::custom(format!("expected {A_NUMBER}")))
            }
            fn visit_seq<A: de::SeqAccess<'de>>(self, _: A) -> Result<Number, A::Error> {
                Err(de::Error::custom(format!(
                    "expected {A_NUMBER}, not a list"
                )))
            }
            fn visit_map<A: de::MapAccess<'de>>(self, _: A) -> Result<Number, A::Error> {
                Err(de::Error::custom(format!("expected {A_NUMBER}, not a map")))
            }
        }
        d.deserialize_any(V)
    }
}

impl<'de> Deserialize<'de> for Whole {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = Whole;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(A_WHOLE)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Whole, E> {
                u32::try_from(v)
                    .map(Whole)
                    .map_err(|_| E::custom(format!("expected {A_WHOLE}")))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Whole, E> {
                u32::try_from(v)
                    .map(Whole)
                    .map_err(|_| E::custom(format!("expected {A_WHOLE}")))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Whole, E> {
                Err(quoted(v, A_WHOLE))
            }
            fn visit_f64<E: de::Error>(self, _: f64) -> Result<Whole, E> {
                Err(E::custom(format!("expected {A_WHOLE}")))
            }
            fn visit_bool<E: de::Error>(self, _: bool) -> Result<Whole, E> {
                Err(E::custom(format!("expected {A_WHOLE}")))
            }
            fn visit_unit<E: de::Error>(self) -> Result<Whole, E> {
                Err(E::custom(format!("expected {A_WHOLE}")))
            }
        }
        d.deserialize_any(V)
    }
}

/// Where a YAML parser's error on `text` lies and what it says, for a message.
#[derive(Clone, Debug, PartialEq)]
pub struct YamlFault {
    /// 1-based line, when known.
    pub line: Option<u64>,
    /// 1-based column, when known.
    pub column: Option<u64>,
    /// The dotted key path at fault (`key_at`), when one is named.
    pub field: Option<String>,
    /// The problem in words.
    pub problem: String,
}

/// A YAML parser's error on `text`: its place, the key it sits under (`key_at`; none
/// when the message names its field itself or concerns the whole file, and the parent's for
/// an unknown field, which the message names), and the problem in words ([`yaml_problem`],
/// with the text found where a number was expected; `fallback` when it says nothing).
pub fn locate(text: &str, e: &serde_saphyr::Error, fallback: &str) -> YamlFault {
    let loc = e.location().filter(|l| l.line() > 0);
    let mut problem = yaml_problem(e, fallback);
    let field = loc.filter(|_| names_no_key(&problem)).and_then(|l| {
        let key = key_at(text, l.line(), l.column())?;
        // The message names the unknown field: the key is its parent's path.
        let unknown = problem
            .strip_prefix("unknown field `")
            .and_then(|r| r.split('`').next());
        match (unknown, key.rsplit_once('.')) {
            (Some(u), Some((parent, last))) if last == u => Some(parent.to_owned()),
            (Some(u), None) if key == u => None,
            _ => Some(key),
        }
    });
    // A missing field is placed at a key of the mapping that lacks it: that mapping's path
    // (`team: missing field ugv`), none at the top level, whose fields the message names.
    let field = field.or_else(|| {
        let l = loc.filter(|_| problem.starts_with("missing field"))?;
        let key = key_at(text, l.line(), l.column())?;
        // A flow mapping is placed at its first key, right after its `{`: there the key
        // found is already the mapping's own.
        let line = text
            .lines()
            .nth(usize::try_from(l.line()).ok()?.checked_sub(1)?)?;
        let before: String = line
            .chars()
            .take(usize::try_from(l.column()).ok()?.saturating_sub(1))
            .collect();
        if before.trim_end().ends_with('{') {
            return Some(key);
        }
        key.rsplit_once('.').map(|(parent, _)| parent.to_owned())
    });
    // The items of the sequences on the way, counted (`obstacles[3].circles[1]`).
    let field = match (field, loc) {
        (Some(f), Some(l)) => Some(indexed(text, &f, (l.line(), l.column())).unwrap_or(f)),
        (f, _) => f,
    };
    // A string where a number belongs already names what was found ([`Number`]).
    if problem.starts_with("expected a")
        && !problem.contains(", not ")
        && let Some(l) = loc
        && let Some(found) = token_at(text, l.line(), l.column())
    {
        problem = format!("{problem}, got '{found}'");
    }
    YamlFault {
        line: loc.map(|l| l.line()),
        column: loc.map(|l| l.column()).filter(|&c| c > 0),
        field,
        problem,
    }
}

/// The most nodes [`indexed`] reads a file's tree of.
const INDEXED_NODES: usize = 1_000_000;

/// A YAML node and the place each of its items starts: the tree in which a parser's error
/// is placed, to count the sequence items on the way to it ([`indexed`]).
enum Node {
    Map(Vec<(String, serde_saphyr::Spanned<Node>)>),
    Seq(Vec<serde_saphyr::Spanned<Node>>),
    Leaf,
}

impl<'de> Deserialize<'de> for Node {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Node;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("any YAML node")
            }
            fn visit_map<A: de::MapAccess<'de>>(self, mut m: A) -> Result<Node, A::Error> {
                let mut entries = Vec::new();
                while let Some(k) = m.next_key::<Key>()? {
                    entries.push((k.0, m.next_value()?));
                }
                Ok(Node::Map(entries))
            }
            fn visit_seq<A: de::SeqAccess<'de>>(self, mut q: A) -> Result<Node, A::Error> {
                let mut items = Vec::new();
                while let Some(item) = q.next_element()? {
                    items.push(item);
                }
                Ok(Node::Seq(items))
            }
            fn visit_bool<E>(self, _: bool) -> Result<Node, E> {
                Ok(Node::Leaf)
            }
            fn visit_i64<E>(self, _: i64) -> Result<Node, E> {
                Ok(Node::Leaf)
            }
            fn visit_u64<E>(self, _: u64) -> Result<Node, E> {
                Ok(Node::Leaf)
            }
            fn visit_i128<E>(self, _: i128) -> Result<Node, E> {
                Ok(Node::Leaf)
            }
            fn visit_u128<E>(self, _: u128) -> Result<Node, E> {
                Ok(Node::Leaf)
            }
            fn visit_f64<E>(self, _: f64) -> Result<Node, E> {
                Ok(Node::Leaf)
            }
            fn visit_str<E>(self, _: &str) -> Result<Node, E> {
                Ok(Node::Leaf)
            }
            fn visit_unit<E>(self) -> Result<Node, E> {
                Ok(Node::Leaf)
            }
            fn visit_none<E>(self) -> Result<Node, E> {
                Ok(Node::Leaf)
            }
        }
        d.deserialize_any(V)
    }
}

/// A mapping's key as text, whatever scalar it is.
struct Key(String);

impl<'de> Deserialize<'de> for Key {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = Key;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a key")
            }
            fn visit_str<E>(self, v: &str) -> Result<Key, E> {
                Ok(Key(v.to_owned()))
            }
            fn visit_bool<E>(self, v: bool) -> Result<Key, E> {
                Ok(Key(v.to_string()))
            }
            fn visit_i64<E>(self, v: i64) -> Result<Key, E> {
                Ok(Key(v.to_string()))
            }
            fn visit_u64<E>(self, v: u64) -> Result<Key, E> {
                Ok(Key(v.to_string()))
            }
            fn visit_f64<E>(self, v: f64) -> Result<Key, E> {
                Ok(Key(v.to_string()))
            }
            fn visit_unit<E>(self) -> Result<Key, E> {
                Ok(Key(String::new()))
            }
        }
        d.deserialize_any(V)
    }
}

/// `key` (a dotted path of [`key_at`]) with the sequence items on the way to `at` (line,
/// column, 1-based) counted: `obstacles[3].circles[1]` for `obstacles.circles`. Each
/// sequence on the way is entered at its last item that starts at or before `at`; after the
/// last key, a sequence of sequences or maps gets its item's index too (`circles[1]`), one of
/// numbers does not (`start`). `None` when the text does not read as YAML or the path does
/// not lead through it (the caller keeps `key`).
fn indexed(text: &str, key: &str, at: (u64, u64)) -> Option<String> {
    // A tree of every node costs tens of bytes a node: a file past a million nodes keeps
    // its key without indices rather than take gigabytes to print an error.
    let root: serde_saphyr::Spanned<Node> = from_yaml_within(text, INDEXED_NODES).ok()?;
    let item = |items| holding(items, at);
    let mut node = &root;
    let mut out = String::new();
    for k in key.split('.') {
        while let Node::Seq(items) = &node.value {
            let (j, n) = item(items)?;
            let _ = write!(out, "[{j}]");
            node = n;
        }
        let Node::Map(entries) = &node.value else {
            return None;
        };
        let (_, v) = entries.iter().find(|(name, _)| name == k)?;
        if !out.is_empty() {
            out.push('.');
        }
        out.push_str(k);
        node = v;
    }
    if let Node::Seq(items) = &node.value
        && let Some((j, n)) = item(items)
        && matches!(n.value, Node::Seq(_) | Node::Map(_))
    {
        let _ = write!(out, "[{j}]");
    }
    Some(out)
}

/// The last of `items` that starts at or before `at` (line, column), and its index: the
/// item that holds `at`.
fn holding(
    items: &[serde_saphyr::Spanned<Node>],
    at: (u64, u64),
) -> Option<(usize, &serde_saphyr::Spanned<Node>)> {
    items
        .iter()
        .enumerate()
        .take_while(|(_, n)| (n.referenced.line(), n.referenced.column()) <= at)
        .last()
}

/// The scalar that starts at `line`, `column` (1-based): up to the next `,`, `]`, `}`,
/// `#` or line end, trimmed; at most 40 characters, escaped.
fn token_at(text: &str, line: u64, column: u64) -> Option<String> {
    let here = text
        .lines()
        .nth(usize::try_from(line).ok()?.checked_sub(1)?)?;
    let rest: String = here
        .chars()
        .skip(usize::try_from(column).ok()?.checked_sub(1)?)
        .take_while(|c| !",]}#".contains(*c))
        .collect();
    let t = rest.trim();
    // A JSON string's own quotes are not part of what was found.
    let t = t
        .strip_prefix('"')
        .and_then(|u| u.strip_suffix('"'))
        .unwrap_or(t);
    (!t.is_empty()).then(|| {
        t.chars()
            .take(40)
            .collect::<String>()
            .escape_debug()
            .to_string()
    })
}

/// What a file that holds a second YAML document is told.
const SECOND_DOCUMENT: &str =
    "a second YAML document starts here (after `---`): the file holds one";

/// Most YAML nodes (maps, sequences and scalars, keys included) an input may hold: about
/// 0.9 million one-circle obstacles in a scene or a world (9 nodes each). The parser's own default
/// (250,000) stopped scenes at about 55,000 circles; the limits on aliases and anchors that
/// guard against expansion bombs stay at the parser's defaults.
pub const MAX_YAML_NODES: usize = 8_000_000;

/// Reads YAML (or JSON, a subset of it) into `T` with the project's limits
/// ([`MAX_YAML_NODES`]): for scene files and the other YAML inputs.
pub fn from_yaml<T: de::DeserializeOwned>(text: &str) -> Result<T, serde_saphyr::Error> {
    from_yaml_within(text, MAX_YAML_NODES)
}

/// [`from_yaml`] with at most `max_nodes` nodes.
pub fn from_yaml_within<T: de::DeserializeOwned>(
    text: &str,
    max_nodes: usize,
) -> Result<T, serde_saphyr::Error> {
    let mut budget = serde_saphyr::budget::Budget::default();
    budget.max_nodes = max_nodes;
    budget.max_events = 2 * max_nodes;
    budget.max_total_scalar_bytes = 1 << 29;
    let mut options = serde_saphyr::Options::default();
    options.budget = Some(budget);
    // [`Number`] reads through `deserialize_any`: NaN and infinities reach it as numbers,
    // and the checks after reading name them ("radius is infinite", "x is NaN").
    options.non_finite_float_policy = serde_saphyr::options::NonFiniteFloatPolicy::PassThrough;
    // Spellings that YAML readers take differently are strings, which [`Number`] refuses:
    // `1_0` (10 to YAML 1.1, a string to 1.2) and `010` (8 to YAML 1.1, 10 to 1.2).
    options.underscored_numbers_as_strings = true;
    options.leading_zero_numbers_as_strings = true;
    serde_saphyr::from_str_with_options(text, options)
}

/// The problem a YAML parser's error states, without its own `error: line L column C: `
/// prefix (the caller reports the location): for scene files and the other YAML inputs
/// (`fallback` when the message is empty).
pub fn yaml_problem(e: &serde_saphyr::Error, fallback: &str) -> String {
    let full = e.to_string();
    let mut msg = full.lines().next().unwrap_or(fallback).trim();
    msg = msg.strip_prefix("error:").unwrap_or(msg).trim_start();
    if let Some(rest) = msg.strip_prefix("line ")
        && let Some((_, tail)) = rest.split_once(": ")
    {
        msg = tail;
    }
    if msg.starts_with("multiple YAML documents") {
        return SECOND_DOCUMENT.to_owned();
    }
    // Serde's names of Rust types ("invalid u32") said in words.
    for (ty, words) in [
        (
            "invalid floating point",
            "expected a finite number (such as 2, -1.5 or 3e-2)",
        ),
        ("invalid u32", "expected a whole number >= 0"),
        ("invalid u64", "expected a whole number >= 0"),
        ("invalid usize", "expected a whole number >= 0"),
        ("invalid i32", "expected a whole number"),
        ("invalid i64", "expected a whole number"),
    ] {
        if msg == ty {
            return words.to_owned();
        }
    }
    if let Some(breach) = msg.strip_prefix("budget breached:") {
        // The parser names the limit in Rust's debug form ("Nodes { nodes: 250001 }"):
        // only its kind is kept, in words ("ScalarBytes": "scalar bytes").
        let kind: String = breach
            .trim()
            .split(|c: char| !c.is_ascii_alphanumeric())
            .next()
            .unwrap_or("size")
            .chars()
            .flat_map(|c| {
                let space = c.is_ascii_uppercase().then_some(' ');
                space.into_iter().chain(c.to_lowercase())
            })
            .collect();
        let kind = kind.trim();
        return if kind == "nodes" {
            format!(
                "exceeds the YAML reader's limit on nodes (at most {MAX_YAML_NODES}, about 0.9 \
                 million one-circle obstacles)"
            )
        } else if kind == "alias anchor ratio" {
            "exceeds the YAML reader's limit on aliases per anchor (once there are 100 \
             aliases, at most 10 per anchor: a guard against expansion bombs)"
                .to_owned()
        } else {
            format!("exceeds the YAML reader's limit on {kind}")
        };
    }
    // The parser's advice names its own options ("set DuplicateKeyPolicy in Options if
    // acceptable"), which a user of a file cannot set.
    if let Some(key) = msg.strip_prefix("duplicate mapping key:") {
        let key = key.split(", set ").next().unwrap_or(key).trim();
        return format!("the key '{key}' is given twice: give each key once");
    }
    msg.to_owned()
}

/// Whether a parser's `problem` is blamed on the key where it stands: not when it names
/// its field itself (`missing field`) or concerns the whole file (a second document).
fn names_no_key(problem: &str) -> bool {
    !(problem.starts_with("missing field") || problem.starts_with(SECOND_DOCUMENT))
}

/// The key a parser's error at `line` and `column` (1-based; column 0 when unknown) sits
/// under, for its message, as a dotted path: the keys of the blocks that hold the line
/// (each less indented than the one below it), then the keys that open before the column
/// on the line itself, nested by `{...}` (or the key that begins it, when the error is
/// placed before it). `bounds.min` for `bounds: {min: [0x0, 0]}`, the
/// same in one-line or pretty JSON, `team.ugv.speed` in a block, `obstacles.circles` for a
/// bad circle (sequence items are not counted). `None` when no key holds the line.
fn key_at(text: &str, line: u64, column: u64) -> Option<String> {
    let n = usize::try_from(line).ok()?.checked_sub(1)?;
    let here = text.lines().nth(n)?;
    let upto: String = if column > 0 {
        here.chars().take(column as usize - 1).collect()
    } else {
        here.to_owned()
    };
    let mut path = Vec::new();
    let mut want = indent_of(here);
    for above in text.lines().take(n).collect::<Vec<_>>().into_iter().rev() {
        if want == 0 {
            break;
        }
        if let Some(key) = keys_on_line(above).into_iter().next()
            && indent_of(above) < want
        {
            want = indent_of(above);
            path.push(key);
        }
    }
    path.reverse();
    // An error placed at the start of a line (a sequence of the wrong length) is the key's
    // that begins it.
    let mut on_line = keys_on_line(&upto);
    if on_line.is_empty() {
        on_line.extend(keys_on_line(here).into_iter().take(1));
    }
    path.extend(on_line);
    (!path.is_empty()).then(|| path.join("."))
}

/// Where a line's content starts, past spaces and sequence dashes (`  - name: a`: 4).
fn indent_of(line: &str) -> usize {
    line.len() - line.trim_start_matches([' ', '-']).len()
}

/// The path of keys open at the end of `text` (one line, cut at the error's column): a
/// key is a word or a quoted string followed by `:`; `{` opens a deeper map, `}` closes it.
/// Comments (`#` outside quotes) end the line.
fn keys_on_line(text: &str) -> Vec<String> {
    // One level per open block (the line itself), `{` or `[`, with the key open in it.
    let mut path: Vec<(char, Option<String>)> = vec![(' ', None)];
    let mut chars = text.chars().peekable();
    let mut word = String::new();
    while let Some(c) = chars.next() {
        match c {
            '"' | '\'' => {
                word = chars.by_ref().take_while(|&q| q != c).collect();
                continue;
            }
            '#' => break,
            '{' | '[' => path.push((c, None)),
            '}' | ']' if path.len() > 1 => {
                path.pop();
            }
            // A comma in a flow map closes its key's value.
            ',' => {
                if let Some((open, key)) = path.last_mut()
                    && *open == '{'
                {
                    *key = None;
                }
            }
            ':' if !word.is_empty()
                && chars
                    .peek()
                    .is_none_or(|n| n.is_whitespace() || "[{\"'".contains(*n)) =>
            {
                if let Some((open, key)) = path.last_mut()
                    && *open != '['
                {
                    *key = Some(std::mem::take(&mut word));
                }
            }
            c if c.is_alphanumeric() || c == '_' || c == '-' => {
                word.push(c);
                continue;
            }
            _ => {}
        }
        word.clear();
    }
    path.into_iter().filter_map(|(_, key)| key).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The key path at `line`, at the column of the first `^` in `marked` (the `^` removed).
    fn key(marked: &str) -> Option<String> {
        let (n, l) = marked
            .lines()
            .enumerate()
            .find(|(_, l)| l.contains('^'))
            .unwrap();
        let col = l.chars().position(|c| c == '^').unwrap() as u64 + 1;
        key_at(&marked.replace('^', ""), n as u64 + 1, col)
    }

    #[test]
    fn the_key_path_follows_blocks_flow_maps_and_json() {
        for (text, want) in [
            (
                "bounds: {min: [^0x0, 0], max: [1, 1]}\n",
                Some("bounds.min"),
            ),
            ("team:\n  ugv:\n    speed: ^fast\n", Some("team.ugv.speed")),
            (
                "obstacles:\n  - name: a\n    circles:\n      - [1, ^2, zz]\n",
                Some("obstacles.circles"),
            ),
            // A sibling flow map that leaves its `{` open is no parent.
            (
                "obstacles:\n  - {name: b,\n     circles: [[1, 2, ^zz]]}\n",
                Some("obstacles.circles"),
            ),
            (
                "{\"name\": \"x\", \"bounds\": {\"min\": [0, 0]},\n \"start\": [5, ^\"q\"]}\n",
                Some("start"),
            ),
            (
                "{\"name\":\"j\",\"bounds\":{\"min\":[0,0],\"max\":[^NaN,60]}}\n",
                Some("bounds.max"),
            ),
            (
                "{\n  \"bounds\": {\n    \"min\": [0, ^NaN]\n  }\n}\n",
                Some("bounds.min"),
            ),
            (
                "name: \"a: b\"\nstart: [5, ^x] # a: comment\n",
                Some("start"),
            ),
            ("^[1, 2]\n", None),
        ] {
            assert_eq!(key(text).as_deref(), want, "{text}");
        }
    }

    #[test]
    fn the_field_counts_the_items_on_the_way() {
        for (text, key, want) in [
            (
                "obstacles:\n  - name: a\n    circles: [[1, 2, 3]]\n  - name: b\n    circles:\n      - [1, 2, 3]\n      - [^1, 2]\n",
                "obstacles.circles",
                "obstacles[1].circles[1]",
            ),
            (
                "{\"obstacles\": [{\"circles\": [[1, 2, 3]]}, {\"circles\": [[1, 2, 3], [1, ^\"x\", 3]]}]}",
                "obstacles.circles",
                "obstacles[1].circles[1]",
            ),
            ("start: [^x, 2]\n", "start", "start"),
            ("hazards: [[1, 2], [^x, 3]]\n", "hazards", "hazards[1]"),
            (
                "team:\n  uavs:\n    - {speed: 1}\n    - {speed: ^fast}\n",
                "team.uavs.speed",
                "team.uavs[1].speed",
            ),
        ] {
            let (n, l) = text
                .lines()
                .enumerate()
                .find(|(_, l)| l.contains('^'))
                .unwrap();
            let col = l.chars().position(|c| c == '^').unwrap() as u64 + 1;
            let got = indexed(&text.replace('^', ""), key, (n as u64 + 1, col));
            assert_eq!(got.as_deref(), Some(want), "{text}");
        }
        // Not YAML, or a path the text does not hold: none (the caller keeps its key).
        assert_eq!(indexed("a: [1, 2", "a", (1, 1)), None);
        assert_eq!(indexed("a: 1\n", "b", (1, 1)), None);
    }

    #[test]
    fn a_missing_field_is_blamed_on_the_mapping_that_lacks_it() {
        #[derive(serde::Deserialize, Debug)]
        #[allow(dead_code)]
        struct Doc {
            #[serde(default)]
            name: String,
            team: Team,
            #[serde(default)]
            points: Vec<Team>,
        }
        #[derive(serde::Deserialize, Debug)]
        #[allow(dead_code)]
        struct Team {
            ugv: u32,
            #[serde(default)]
            uavs: Vec<u32>,
        }
        for (text, want) in [
            ("name: x\nteam:\n  uavs: []\n", Some("team")),
            ("name: x\nteam: {uavs: []}\n", Some("team")),
            ("{\"name\": \"x\", \"team\": {\"uavs\": []}}", Some("team")),
            (
                "team: {ugv: 1}\npoints:\n  - {ugv: 2}\n  - {uavs: []}\n",
                Some("points[1]"),
            ),
            ("name: x\n", None),
        ] {
            let e = from_yaml::<Doc>(text).unwrap_err();
            let f = locate(text, &e, "malformed");
            assert!(
                f.problem.starts_with("missing field"),
                "{text}: {}",
                f.problem
            );
            assert_eq!(f.field.as_deref(), want, "{text}");
        }
    }

    #[test]
    fn numbers_are_plain_scalars_never_quoted_strings() {
        for (text, want) in [
            ("[5, -2.5, 3e-2, 7]", Ok([5.0, -2.5, 0.03, 7.0])),
            // YAML 1.2's integer forms are numbers, read exactly.
            ("[0x10, 0o10, -0, 1e2]", Ok([16.0, 8.0, 0.0, 100.0])),
            // Spellings that YAML 1.1 and 1.2 read differently are refused.
            (
                "[1_0, 0, 0, 0]",
                Err("not '1_0': YAML 1.1 reads digits with underscores"),
            ),
            (
                "[010, 0, 0, 0]",
                Err("not '010': YAML 1.1 reads a leading zero as octal"),
            ),
            // A hex or octal number beyond 64 bits is named as too large.
            (
                "[0xFFFFFFFFFFFFFFFFFFFF, 0, 0, 0]",
                Err("not '0xFFFFFFFFFFFFFFFFFFFF': too large for a whole number"),
            ),
            (
                "[0o7777777777777777777777777, 0, 0, 0]",
                Err("too large for a whole number"),
            ),
            // Quoted, a hex number that fits is a string like any other.
            ("['0x10', 0, 0, 0]", Err("not the string '0x10'")),
            ("[0.5, 00.5, 0, 0]", Ok([0.5, 0.5, 0.0, 0.0])),
            ("[NaN, 0, 0, 0]", Err("not 'NaN': it must be finite")),
            (
                "[-Infinity, 0, 0, 0]",
                Err("not '-Infinity': it must be finite"),
            ),
            ("[5, '30', 1, 1]", Err("not the string '30'")),
            ("[\"5\", 30, 1, 1]", Err("not the string '5'")),
            ("[five, 30, 1, 1]", Err("not the string 'five'")),
            ("[null, 30, 1, 1]", Err("expected a number (such as")),
            ("[true, 30, 1, 1]", Err("expected a number (such as")),
            ("[[1], 30, 1, 1]", Err("without quotes), not a list")),
        ] {
            let got = from_yaml::<[Number; 4]>(text).map(|a| a.map(|n| n.0));
            match (got, want) {
                (Ok(a), Ok(w)) => assert_eq!(a, w, "{text}"),
                (Err(e), Err(w)) => assert!(e.to_string().contains(w), "{text}: {e}"),
                (got, _) => panic!("{text}: {got:?}"),
            }
        }
        assert_eq!(from_yaml::<Whole>("1").unwrap(), Whole(1));
        for (text, want) in [
            ("'1'", "not the string '1'"),
            ("\"1\"", "not the string '1'"),
            ("-1", "expected a whole number >= 0 (without quotes)"),
            ("1.5", "expected a whole number >= 0 (without quotes)"),
            (
                "4294967296",
                "expected a whole number >= 0 (without quotes)",
            ),
        ] {
            let e = from_yaml::<Whole>(text).unwrap_err().to_string();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
