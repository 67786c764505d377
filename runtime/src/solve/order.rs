//! Elimination orders for the sparse direct solver, written from the textbook
//! algorithms (Tarjan and Yannakakis 1984 for chordal graphs; Rose's minimum degree,
//! George and Liu 1989).
//!
//! * If the graph is chordal (every cycle of four or more vertices has a chord), the
//!   reverse of a maximum cardinality search is a perfect elimination ordering: no
//!   fill at all. Link graphs of particle trees are chordal: the links at one particle
//!   form a clique and two cliques share at most one link, so a branching hair or a
//!   tree of links is factored with zero fill, in time linear in the number of entries.
//! * Otherwise (cloth, meshes with loops) multiple minimum degree on the explicit
//!   elimination graph: eliminate vertices of least current degree, not adjacent to one
//!   another within a round, and join each one's neighbours into a clique; and the
//!   same with the most recently updated vertex first; the one whose factor costs
//!   less is kept. Its cost is about twice that of the symbolic factorisation (the
//!   work is the sum over eliminated vertices of degree times neighbour degree), done
//!   once per pattern.

use std::collections::VecDeque;

use super::Structure;

/// How an order was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum OrderKind {
    /// Perfect elimination ordering of a chordal graph (no fill).
    Perfect,
    /// Minimum degree.
    MinimumDegree,
}

/// An elimination order (`order[k]` is the vertex eliminated `k`-th) for the graph of
/// `st`.
pub(crate) fn elimination_order(st: &Structure) -> (Vec<usize>, OrderKind) {
    let mcs = maximum_cardinality_search(st);
    if is_perfect(st, &mcs) {
        (mcs, OrderKind::Perfect)
    } else {
        (minimum_degree(st), OrderKind::MinimumDegree)
    }
}

/// Reverse of the visit order of a maximum cardinality search: visit next the vertex
/// with most visited neighbours. `O(n + e)` with lazily cleaned weight buckets.
fn maximum_cardinality_search(st: &Structure) -> Vec<usize> {
    let n = st.m;
    let mut weight = vec![0usize; n];
    let mut visited = vec![false; n];
    let mut buckets: Vec<Vec<usize>> = vec![(0..n).rev().collect()];
    let mut top = 0;
    let mut visit = Vec::with_capacity(n);
    while visit.len() < n {
        let v = loop {
            match buckets[top].pop() {
                Some(v) if !visited[v] && weight[v] == top => break v,
                Some(_) => {}
                None => top -= 1,
            }
        };
        visited[v] = true;
        visit.push(v);
        for &u in st.neighbours(v) {
            if !visited[u] {
                weight[u] += 1;
                let w = weight[u];
                if w == buckets.len() {
                    buckets.push(Vec::new());
                }
                buckets[w].push(u);
                top = top.max(w);
            }
        }
    }
    visit.reverse();
    visit
}

/// Whether eliminating in `order` creates no fill: for every vertex, its neighbours
/// eliminated later must all be adjacent to the first of them.
fn is_perfect(st: &Structure, order: &[usize]) -> bool {
    let n = st.m;
    let mut pos = vec![0; n];
    for (k, &v) in order.iter().enumerate() {
        pos[v] = k;
    }
    for &v in order {
        let later = st.neighbours(v).iter().filter(|&&u| pos[u] > pos[v]);
        let Some(&first) = later.clone().min_by_key(|&&u| pos[u]) else {
            continue;
        };
        let first_nbrs = st.neighbours(first);
        for &w in later {
            if w != first && first_nbrs.binary_search(&w).is_err() {
                return false;
            }
        }
    }
    true
}

/// The better of two minimum degree orders by the work of the factorisation they give
/// (`sum` of the squared column counts of `L`, which the elimination graph shows for
/// free: a vertex's neighbours when it is eliminated are its column's rows).
///
/// Minimum degree leaves the choice among vertices of equal degree open, and on meshes
/// that choice sets the fill: neither of the two rules below is the better on every
/// numbering of the same cloth (64 x 64, `J_Omega`'s 55,684 nonzeros: 13.6 values per
/// nonzero for [`Ties::LastUpdated`] and 9.6 for [`Ties::Rounds`] with the links
/// numbered row by row; 11.6-11.9 and 12.0-12.5 numbered at random), so both are run
/// and the cheaper kept, as sparse packages keep the best of several orderings.
fn minimum_degree(st: &Structure) -> Vec<usize> {
    let (a, work_a) = minimum_degree_with(st, Ties::Rounds);
    let (b, work_b) = minimum_degree_with(st, Ties::LastUpdated);
    if work_a <= work_b { a } else { b }
}

/// How minimum degree chooses among vertices of the least degree.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Ties {
    /// The most recently updated first (each elimination tends to take a neighbour of
    /// the last one, growing one clique).
    LastUpdated,
    /// Multiple minimum degree (Liu, ACM TOMS 11, 1985): in rounds, first in first out,
    /// each round eliminating vertices of the least degree that are not neighbours of
    /// one eliminated in the same round, so that the eliminations spread over the graph.
    Rounds,
}

/// Minimum degree on the explicit elimination graph (sorted adjacency lists, degree
/// buckets with lazy deletion); the order and the work `sum deg^2` of its factor.
fn minimum_degree_with(st: &Structure, ties: Ties) -> (Vec<usize>, f64) {
    let n = st.m;
    let mut adj: Vec<Vec<u32>> = (0..n)
        .map(|i| st.neighbours(i).iter().map(|&j| j as u32).collect())
        .collect();
    let mut eliminated = vec![false; n];
    let max_deg = adj.iter().map(Vec::len).max().unwrap_or(0);
    let mut buckets: Vec<VecDeque<u32>> = vec![VecDeque::new(); max_deg + 1];
    // Popped from the back with `LastUpdated` (vertex 0 first at the start), from the
    // front in rounds.
    let fifo = ties == Ties::Rounds;
    for i in 0..n {
        let v = if fifo { i } else { n - 1 - i };
        buckets[adj[v].len()].push_back(v as u32);
    }
    let mut low = 0;
    let mut order = Vec::with_capacity(n);
    let mut work = 0.0;
    let mut merged: Vec<u32> = Vec::new();
    // Rounds: the round in which each vertex's neighbourhood last changed, and the
    // vertices of the least degree put off to the next round for it.
    let mut touched = vec![0u32; n];
    let mut round = 1u32;
    let mut deferred: Vec<u32> = Vec::new();
    while order.len() < n {
        let v = loop {
            let next = if fifo {
                buckets[low].pop_front()
            } else {
                buckets[low].pop_back()
            };
            match next {
                Some(v) if !eliminated[v as usize] && adj[v as usize].len() == low => {
                    if fifo && touched[v as usize] == round {
                        deferred.push(v);
                    } else {
                        break v as usize;
                    }
                }
                Some(_) => {}
                None if deferred.is_empty() => low += 1,
                None => {
                    // The round is over: its neighbours' degrees are current again.
                    round += 1;
                    for u in deferred.drain(..) {
                        let d = adj[u as usize].len();
                        buckets[d].push_back(u);
                        low = low.min(d);
                    }
                }
            }
        };
        eliminated[v] = true;
        order.push(v);
        let nb = std::mem::take(&mut adj[v]);
        work += (nb.len() * nb.len()) as f64;
        for &u in &nb {
            let u = u as usize;
            // adj[u] <- (adj[u] ∪ nb) \ {u, v}, both sorted.
            merged.clear();
            let (a, b) = (&adj[u], &nb);
            let (mut i, mut j) = (0, 0);
            while i < a.len() || j < b.len() {
                let next = if j == b.len() || (i < a.len() && a[i] < b[j]) {
                    i += 1;
                    a[i - 1]
                } else if i == a.len() || b[j] < a[i] {
                    j += 1;
                    b[j - 1]
                } else {
                    i += 1;
                    j += 1;
                    a[i - 1]
                };
                if next as usize != u && next as usize != v {
                    merged.push(next);
                }
            }
            std::mem::swap(&mut adj[u], &mut merged);
            let d = adj[u].len();
            if d >= buckets.len() {
                buckets.resize(d + 1, VecDeque::new());
            }
            buckets[d].push_back(u as u32);
            touched[u] = round;
            low = low.min(d);
        }
    }
    (order, work)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn graph(m: usize, edges: &[(usize, usize)]) -> Structure {
        let mut p: Vec<(usize, usize)> = (0..m).map(|i| (i, i)).collect();
        for &(i, j) in edges {
            p.push((i, j));
            p.push((j, i));
        }
        Structure::new(m, &p).unwrap()
    }

    #[test]
    fn trees_and_cliques_of_links_are_perfect() {
        // Three links meeting at a particle (a triangle of the link graph) with a tail.
        let st = graph(5, &[(0, 1), (1, 2), (0, 2), (2, 3), (3, 4)]);
        let (order, kind) = elimination_order(&st);
        assert_eq!(kind, OrderKind::Perfect);
        assert!(is_perfect(&st, &order));
    }

    #[test]
    fn a_four_cycle_is_not_chordal_and_gets_minimum_degree() {
        let st = graph(4, &[(0, 1), (1, 2), (2, 3), (3, 0)]);
        assert!(!is_perfect(&st, &[0, 1, 2, 3]));
        let (order, kind) = elimination_order(&st);
        assert_eq!(kind, OrderKind::MinimumDegree);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, vec![0, 1, 2, 3]);
    }

    /// The link graph of a `w x w` grid of particles (links adjacent where they share
    /// a particle), links numbered row by row, or in the order `perm` gives.
    fn cloth(w: usize, perm: Option<&[usize]>) -> Structure {
        let mut links = Vec::new();
        for r in 0..w {
            for c in 0..w {
                let i = r * w + c;
                if c + 1 < w {
                    links.push((i, i + 1));
                }
                if r + 1 < w {
                    links.push((i, i + w));
                }
            }
        }
        let m = links.len();
        let label = |l: usize| perm.map_or(l, |p| p[l]);
        let mut at: Vec<Vec<usize>> = vec![Vec::new(); w * w];
        for (l, &(a, b)) in links.iter().enumerate() {
            at[a].push(label(l));
            at[b].push(label(l));
        }
        let mut edges = Vec::new();
        for ls in &at {
            for (k, &a) in ls.iter().enumerate() {
                for &b in &ls[k + 1..] {
                    edges.push((a, b));
                }
            }
        }
        graph(m, &edges)
    }

    fn work(st: &Structure, order: &[usize]) -> f64 {
        // Eliminate in `order` on the explicit graph: `sum` of squared degrees.
        let n = st.m;
        let mut adj: Vec<std::collections::BTreeSet<usize>> = (0..n)
            .map(|i| st.neighbours(i).iter().copied().collect())
            .collect();
        let mut total = 0.0;
        for &v in order {
            let nb: Vec<usize> = std::mem::take(&mut adj[v]).into_iter().collect();
            total += (nb.len() * nb.len()) as f64;
            for &u in &nb {
                adj[u].remove(&v);
                adj[u].extend(nb.iter().copied().filter(|&x| x != u));
            }
        }
        total
    }

    #[test]
    fn the_cheaper_of_the_two_tie_rules_is_kept_on_either_numbering_of_a_cloth() {
        let w = 24;
        let m = 2 * w * (w - 1);
        // A fixed shuffle of the link numbers.
        let mut perm: Vec<usize> = (0..m).collect();
        let mut state = 2u64;
        for i in (1..m).rev() {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
            perm.swap(i, (state >> 33) as usize % (i + 1));
        }
        let mut chosen = Vec::new();
        for st in [cloth(w, None), cloth(w, Some(&perm))] {
            let (rounds, work_rounds) = minimum_degree_with(&st, Ties::Rounds);
            let (last, work_last) = minimum_degree_with(&st, Ties::LastUpdated);
            // The work each reports is the work of its order.
            assert_eq!(work_rounds, work(&st, &rounds));
            assert_eq!(work_last, work(&st, &last));
            let order = minimum_degree(&st);
            let mut sorted = order.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..m).collect::<Vec<_>>());
            assert_eq!(work(&st, &order), work_rounds.min(work_last));
            chosen.push((work_rounds, work_last));
        }
        // Numbered row by row, rounds need far less work than the last-updated rule;
        // numbered in this shuffle, a little more (so each rule is kept once).
        let (rounds, last) = chosen[0];
        assert!(rounds < 0.7 * last, "{rounds} {last}");
        let (rounds, last) = chosen[1];
        assert!(last < rounds, "{rounds} {last}");
    }
}
