//! Reserved words and "did you mean" suggestions.

use crate::Func;

/// The keywords of the language (function names are reserved as well).
pub(super) const KEYWORDS: [&str; 8] = [
    "model",
    "param",
    "state",
    "alg",
    "let",
    "der",
    "constraint",
    "t",
];

/// Whether `name` is a keyword or a built-in function name.
pub(super) fn is_reserved(name: &str) -> bool {
    KEYWORDS.contains(&name) || Func::from_name(name).is_some()
}

/// The diagnostic text for a reserved word used as a name: (message, hint).
pub(super) fn reserved_message(name: &str) -> (String, String) {
    let what = if name == "t" {
        "`t` is reserved for time".to_string()
    } else if Func::from_name(name).is_some() {
        format!("`{name}` is the name of a built-in function")
    } else {
        format!("`{name}` is a keyword")
    };
    (
        format!("reserved word `{name}` cannot be used as a name ({what})"),
        format!("choose another name, e.g. `{name}_` or `{name}1`"),
    )
}

/// Edit distance (insertions, deletions, substitutions, transpositions of neighbours).
fn distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    // Three rolling rows: the transposition case looks two rows back.
    let mut prev2 = vec![0usize; b.len() + 1];
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0usize; b.len() + 1];
    for i in 1..=a.len() {
        cur[0] = i;
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            cur[j] = (prev[j] + 1).min(cur[j - 1] + 1).min(prev[j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                cur[j] = cur[j].min(prev2[j - 2] + 1);
            }
        }
        std::mem::swap(&mut prev2, &mut prev);
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

/// The candidate closest to `name`, if it is close enough to be a likely typo: at most
/// one edit for names of two to four characters, two for longer ones (ties: the first
/// candidate). A name differing only in case is always suggested; a one-letter name
/// gets no other suggestion (every one-letter name is one edit from it).
pub(super) fn suggest<'a>(
    name: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    let limit = match name.chars().count() {
        0 | 1 => 0,
        2..=4 => 1,
        _ => 2,
    };
    let mut best: Option<(usize, &str)> = None;
    for c in candidates {
        if c == name {
            continue;
        }
        let d = if c.eq_ignore_ascii_case(name) {
            0
        } else {
            distance(name, c)
        };
        if d <= limit && best.is_none_or(|(bd, _)| d < bd) {
            best = Some((d, c));
        }
    }
    best.map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_counts_edits_and_transpositions() {
        assert_eq!(distance("abc", "abc"), 0);
        assert_eq!(distance("abc", "abd"), 1);
        assert_eq!(distance("abc", "ab"), 1);
        assert_eq!(distance("abc", "acb"), 1);
        assert_eq!(distance("kitten", "sitting"), 3);
        assert_eq!(distance("", "xy"), 2);
    }

    #[test]
    fn suggest_picks_close_names_only() {
        let names = ["l1", "l2", "length", "vx1"];
        assert_eq!(suggest("l3", names), Some("l1"));
        assert_eq!(suggest("lenght", names), Some("length"));
        assert_eq!(suggest("VX1", names), Some("vx1"));
        assert_eq!(suggest("omega", names), None);
        assert_eq!(suggest("q", ["a", "x"]), None);
        assert_eq!(suggest("X", ["a", "x"]), Some("x"));
        assert_eq!(suggest("sine", Func::ALL.map(Func::name)), Some("sin"));
    }

    #[test]
    fn reserved_words_are_keywords_and_functions() {
        for w in [
            "model",
            "param",
            "state",
            "alg",
            "let",
            "der",
            "constraint",
            "t",
        ] {
            assert!(is_reserved(w), "{w}");
        }
        for f in Func::ALL {
            assert!(is_reserved(f.name()), "{}", f.name());
        }
        assert!(!is_reserved("x"));
        assert!(!is_reserved("time"));
    }
}
