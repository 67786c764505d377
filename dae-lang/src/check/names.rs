//! Reserved words and "did you mean" suggestions.

use crate::Func;
use crate::ast::Span;
use crate::diag::Diagnostic;
use std::collections::HashMap;

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

/// A name declared a second time; `kind` and `first_kind` are what each declaration
/// makes of it, in words (`a parameter`).
pub(super) fn declared_twice(
    name: &str,
    span: Span,
    kind: &str,
    first: Span,
    first_kind: &str,
) -> Diagnostic {
    Diagnostic::new(
        format!("`{name}` is declared twice"),
        span,
        format!("declared again here, as {kind}"),
    )
    .related(first, format!("first declared here, as {first_kind}"))
    .hint("rename one of them: each name in a model means one thing")
}

/// Longest name whose misspellings are searched: a longer name only gets a suggestion
/// that differs from it in case (a typo in a 100-character name is not what happened).
const MAX_TYPO_LEN: usize = 64;

/// The work one [`Suggestions`] may do over all its searches, in candidates looked at
/// plus cells of edit-distance tables: about 0.1 s. A model with thousands of unknown
/// names that are each close to thousands of declared ones gets suggestions for the
/// first ones only, instead of a search quadratic in its size.
const WORK_BUDGET: u64 = 1 << 24;

/// The largest edit distance suggested for a name of `len` characters: one edit for names
/// of two to four characters, two for longer ones, none for one-letter names (every
/// one-letter name is one edit from it).
fn typo_limit(len: usize) -> usize {
    match len {
        0 | 1 => 0,
        2..=4 => 1,
        _ => 2,
    }
}

/// The edit distance of `a` and `b` (insertions, deletions, substitutions,
/// transpositions of neighbours) if it is at most `k`, else `None`.
///
/// Only the band `|i - j| <= k` of the table is computed, and the search stops at the
/// first row whose cells all exceed `k`: at most `(2k + 1) * (len(a) + 1)` cells, each
/// counted in `work`.
fn distance_within(a: &[u8], b: &[u8], k: usize, work: &mut u64) -> Option<usize> {
    let (n, m) = (a.len(), b.len());
    if n.abs_diff(m) > k {
        return None;
    }
    // Larger than any distance, and safe to add 1 to.
    const FAR: usize = usize::MAX / 2;
    // Three rolling rows: the transposition case looks two rows back. A cell outside
    // the band of its row holds FAR.
    let mut prev2 = vec![FAR; m + 1];
    let mut prev: Vec<usize> = (0..=m).map(|j| if j <= k { j } else { FAR }).collect();
    let mut cur = vec![FAR; m + 1];
    for i in 1..=n {
        let lo = i.saturating_sub(k).max(1);
        let hi = (i + k).min(m);
        cur[0] = if i <= k { i } else { FAR };
        if lo > 1 {
            cur[lo - 1] = FAR;
        }
        if hi < m {
            cur[hi + 1] = FAR;
        }
        let mut row_min = cur[0];
        for j in lo..=hi {
            *work += 1;
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut d = (prev[j] + 1).min(cur[j - 1] + 1).min(prev[j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d = d.min(prev2[j - 2] + 1);
            }
            cur[j] = d;
            row_min = row_min.min(d);
        }
        if row_min > k {
            return None;
        }
        std::mem::swap(&mut prev2, &mut prev);
        std::mem::swap(&mut prev, &mut cur);
    }
    (prev[m] <= k).then_some(prev[m])
}

/// The suggestion for one name among `candidates` (see [`Suggestions`]; for a single
/// question: a checker that asks many keeps one [`Suggestions`]).
pub(super) fn suggest<'a>(
    name: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    Suggestions::new(candidates).suggest(name)
}

/// "Did you mean" over a fixed list of names, with bounded work.
///
/// The candidate closest to a name, if it is close enough to be a likely typo (see
/// [`typo_limit`]; ties: the first candidate); a candidate differing only in case is
/// always suggested. Each distinct name is searched once, only among the candidates
/// whose length is within the limit, names longer than [`MAX_TYPO_LEN`] only for case,
/// and all searches together stop after [`WORK_BUDGET`]: the cost is linear in the
/// number of names asked about, whatever the input.
pub(super) struct Suggestions<'a> {
    /// `(length, position, name)` of each candidate, sorted.
    by_len: Vec<(usize, usize, &'a str)>,
    /// Lower-case name -> the first candidate with it.
    folded: HashMap<String, &'a str>,
    /// Answers given so far.
    cache: HashMap<String, Option<&'a str>>,
    /// Work done so far (see [`WORK_BUDGET`]).
    work: u64,
}

impl<'a> Suggestions<'a> {
    /// Suggestions among `candidates`, in their order.
    pub(super) fn new(candidates: impl IntoIterator<Item = &'a str>) -> Self {
        let mut by_len = Vec::new();
        let mut folded = HashMap::new();
        for (k, c) in candidates.into_iter().enumerate() {
            by_len.push((c.len(), k, c));
            folded.entry(c.to_ascii_lowercase()).or_insert(c);
        }
        by_len.sort_unstable();
        Suggestions {
            by_len,
            folded,
            cache: HashMap::new(),
            work: 0,
        }
    }

    /// The suggestion for `name`, if there is one.
    pub(super) fn suggest(&mut self, name: &str) -> Option<&'a str> {
        if let Some(&known) = self.cache.get(name) {
            return known;
        }
        let found = self.search(name);
        self.cache.insert(name.to_string(), found);
        found
    }

    fn search(&mut self, name: &str) -> Option<&'a str> {
        self.work += name.len() as u64;
        if let Some(&c) = self.folded.get(&name.to_ascii_lowercase()) {
            if c != name {
                return Some(c);
            }
        }
        let limit = typo_limit(name.len());
        if limit == 0 || name.len() > MAX_TYPO_LEN {
            return None;
        }
        let from = self
            .by_len
            .partition_point(|(len, _, _)| *len + limit < name.len());
        let mut best: Option<(usize, usize, &'a str)> = None;
        for &(len, k, c) in &self.by_len[from..] {
            if len > name.len() + limit || self.work > WORK_BUDGET {
                break;
            }
            self.work += 1;
            if c == name {
                continue;
            }
            let within = best.map_or(limit, |(d, _, _)| d);
            if let Some(d) = distance_within(name.as_bytes(), c.as_bytes(), within, &mut self.work)
            {
                if best.is_none_or(|(bd, bk, _)| (d, k) < (bd, bk)) {
                    best = Some((d, k, c));
                }
            }
        }
        best.map(|(_, _, c)| c)
    }

    #[cfg(test)]
    fn work(&self) -> u64 {
        self.work
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The whole edit-distance table: the oracle of the banded one.
    fn distance(a: &str, b: &str) -> usize {
        let (a, b) = (a.as_bytes(), b.as_bytes());
        let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
        for (i, row) in d.iter_mut().enumerate() {
            row[0] = i;
        }
        for (j, cell) in d[0].iter_mut().enumerate() {
            *cell = j;
        }
        for i in 1..=a.len() {
            for j in 1..=b.len() {
                let cost = usize::from(a[i - 1] != b[j - 1]);
                let mut v = (d[i - 1][j] + 1)
                    .min(d[i][j - 1] + 1)
                    .min(d[i - 1][j - 1] + cost);
                if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                    v = v.min(d[i - 2][j - 2] + 1);
                }
                d[i][j] = v;
            }
        }
        d[a.len()][b.len()]
    }

    fn suggest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
        Suggestions::new(candidates).suggest(name)
    }

    #[test]
    fn distance_counts_edits_and_transpositions() {
        assert_eq!(distance("abc", "abc"), 0);
        assert_eq!(distance("abc", "abd"), 1);
        assert_eq!(distance("abc", "ab"), 1);
        assert_eq!(distance("abc", "acb"), 1);
        assert_eq!(distance("kitten", "sitting"), 3);
        assert_eq!(distance("", "xy"), 2);
    }

    /// Every pair of words of up to 4 letters over `a b c`, every bound up to 3.
    #[test]
    fn the_banded_distance_agrees_with_the_whole_table() {
        let mut words = vec![String::new()];
        for len in 1..=4 {
            let shorter: Vec<String> = words
                .iter()
                .filter(|w| w.len() == len - 1)
                .cloned()
                .collect();
            for w in shorter {
                for c in ["a", "b", "c"] {
                    words.push(format!("{w}{c}"));
                }
            }
        }
        let mut work = 0;
        for a in &words {
            for b in &words {
                let d = distance(a, b);
                for k in 0..=3 {
                    let banded = distance_within(a.as_bytes(), b.as_bytes(), k, &mut work);
                    assert_eq!(banded, (d <= k).then_some(d), "{a:?} {b:?} k = {k}");
                }
            }
        }
    }

    #[test]
    fn the_banded_distance_computes_the_band_only() {
        let a = "x".repeat(100_000);
        let mut b = a.clone();
        b.replace_range(50_000..50_001, "y");
        let mut work = 0;
        assert_eq!(
            distance_within(a.as_bytes(), b.as_bytes(), 2, &mut work),
            Some(1)
        );
        assert!(work <= 5 * 100_000, "{work} cells");
        // Far apart from the start: stops after a few rows.
        let mut work = 0;
        let c = "y".repeat(100_000);
        assert_eq!(
            distance_within(a.as_bytes(), c.as_bytes(), 2, &mut work),
            None
        );
        assert!(work <= 20, "{work} cells");
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
        // The closest wins over the first; among equally close, the first declared.
        assert_eq!(suggest("speed", ["spead1", "sped", "speeds"]), Some("sped"));
        assert_eq!(suggest("abcde", ["abxye", "abcxx", "xbcde"]), Some("xbcde"));
        assert_eq!(suggest("abcde", ["abcxx", "abxye"]), Some("abcxx"));
    }

    /// A misspelt 100,000-character name, near 100 others: no typo search (only the case
    /// lookup), so work proportional to its length, not to the square of it.
    #[test]
    fn a_long_name_costs_its_length() {
        let long = "a".repeat(100_000);
        let declared: Vec<String> = (0..100).map(|k| format!("{long}{k}")).collect();
        let mut s = Suggestions::new(declared.iter().map(String::as_str));
        assert_eq!(s.suggest(&format!("{long}x")), None);
        let upper = long.to_ascii_uppercase() + "7";
        assert_eq!(s.suggest(&upper), Some(declared[7].as_str()));
        assert!(s.work() <= 200_002 + 2, "{} units of work", s.work());
    }

    /// 8,000 distinct unknown names, each close to 8,000 declared ones: the searches stop
    /// at the budget instead of comparing 64 million pairs, and a repeated name is not
    /// searched again.
    #[test]
    fn many_unknown_names_cost_at_most_the_budget() {
        let declared: Vec<String> = (0..8000).map(|k| format!("v{k:04}")).collect();
        let unknown: Vec<String> = (0..8000).map(|k| format!("w{k:04}")).collect();
        let mut s = Suggestions::new(declared.iter().map(String::as_str));
        assert_eq!(s.suggest("w0000"), Some("v0000"));
        for u in &unknown {
            s.suggest(u);
        }
        // Past the budget, each name still costs its case lookup (its length).
        let after = s.work();
        assert!(after <= WORK_BUDGET + 8001 * 6, "{after}");
        for u in &unknown {
            s.suggest(u);
        }
        assert_eq!(s.work(), after, "answers are cached");
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
