//! Short class ids for people: a class's signature when it is short, else a hash of it, so
//! that tables, legends and `--avoid` can name a class whose signature runs to a hundred
//! letters (maps), and letters by rank (A, B, C...) for the names people say. The plan JSON
//! keeps the whole signature beside both.

/// Signatures up to this many characters are their own id.
pub const ID_MAX_CHARS: usize = 12;

/// The id of the class whose signature prints as `signature`: the signature itself when it
/// has at most [`ID_MAX_CHARS`] characters, else `#` and eight hex digits of its FNV-1a hash
/// (64 bits, folded to 32). Two classes of one plan share an id with a chance of about
/// `k^2 / 2^33` (2.4e-7 for 64 classes).
pub fn class_id(signature: &str) -> String {
    if signature.chars().count() <= ID_MAX_CHARS {
        return signature.to_owned();
    }
    let h = signature.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    });
    format!("#{:08x}", (h ^ (h >> 32)) as u32)
}

/// Whether `text` has the form of a hashed id: `#` and eight lower-case hex digits, as
/// [`class_id`] writes them (an upper-case id would match no class).
pub fn is_hashed_id(text: &str) -> bool {
    text.strip_prefix('#').is_some_and(|h| {
        h.len() == 8
            && h.bytes()
                .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
    })
}

/// The letter of the class of rank `rank` (1 is the best): A to Z, then AA, AB... as
/// spreadsheet columns; `?` for rank 0. Letters name a plan's classes in tables, legends
/// and mission events ("route B"); they hold within one plan (or one mission), where
/// [`class_id`] holds everywhere.
///
/// # Examples
///
/// ```
/// use homospline_homotopy::class_letter;
///
/// assert_eq!(class_letter(1), "A");
/// assert_eq!(class_letter(26), "Z");
/// assert_eq!(class_letter(27), "AA");
/// assert_eq!(class_letter(703), "AAA");
/// ```
pub fn class_letter(rank: usize) -> String {
    if rank == 0 {
        return "?".to_owned();
    }
    let mut n = rank;
    let mut out = Vec::new();
    while n > 0 {
        let r = (n - 1) % 26;
        out.push(b'A' + r as u8);
        n = (n - 1) / 26;
    }
    out.reverse();
    String::from_utf8(out).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn letters_count_as_spreadsheet_columns() {
        let all: Vec<String> = (1..=800).map(class_letter).collect();
        assert_eq!(&all[..3], ["A", "B", "C"]);
        assert_eq!(
            (all[25].as_str(), all[26].as_str(), all[51].as_str()),
            ("Z", "AA", "AZ")
        );
        assert_eq!((all[701].as_str(), all[702].as_str()), ("ZZ", "AAA"));
        let mut distinct = all.clone();
        distinct.sort();
        distinct.dedup();
        assert_eq!(distinct.len(), all.len(), "every rank its own letters");
    }

    #[test]
    fn short_signatures_are_their_own_ids_and_long_ones_are_told_apart() {
        assert_eq!(class_id("e"), "e");
        assert_eq!(class_id("-1+2-10+11"), "-1+2-10+11");
        let a: String = (1..=40).map(|i| format!("-{i}")).collect();
        let b = a.replacen("-20", "+20", 1);
        let (ia, ib) = (class_id(&a), class_id(&b));
        assert!(is_hashed_id(&ia) && is_hashed_id(&ib), "{ia} {ib}");
        assert_ne!(ia, ib);
        assert_eq!(ia, class_id(&a), "the same signature, the same id");
        assert!(!is_hashed_id("-1+2") && !is_hashed_id("#12345") && !is_hashed_id("#1234567g"));
        assert!(
            !is_hashed_id(&ia.to_uppercase()),
            "ids are lower case, as printed"
        );
    }
}
