//! Short class ids for people: a class's signature when it is short, else a hash of it, so
//! that tables, legends and `--avoid` can name a class whose signature runs to a hundred
//! letters (maps). The plan JSON keeps the whole signature.

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

#[cfg(test)]
mod tests {
    use super::*;

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
