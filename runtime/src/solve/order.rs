//! Elimination orders for the sparse direct solver, written from the textbook
//! algorithms (Tarjan and Yannakakis 1984 for chordal graphs; Rose's minimum degree,
//! George and Liu 1989).
//!
//! * If the graph is chordal (every cycle of four or more vertices has a chord), the
//!   reverse of a maximum cardinality search is a perfect elimination ordering: no
//!   fill at all. Link graphs of particle trees are chordal: the links at one particle
//!   form a clique and two cliques share at most one link, so a branching hair or a
//!   tree of links is factored with zero fill, in time linear in the number of entries.
//! * Otherwise (cloth, meshes with loops) minimum degree on the explicit elimination
//!   graph: eliminate a vertex of least current degree and join its neighbours into a
//!   clique. Its cost is about that of the symbolic factorisation (the work is the sum
//!   over eliminated vertices of degree times neighbour degree), done once per pattern.

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

/// Minimum degree on the explicit elimination graph (sorted adjacency lists, degree
/// buckets with lazy deletion; ties go to the most recently updated vertex).
fn minimum_degree(st: &Structure) -> Vec<usize> {
    let n = st.m;
    let mut adj: Vec<Vec<u32>> = (0..n)
        .map(|i| st.neighbours(i).iter().map(|&j| j as u32).collect())
        .collect();
    let mut eliminated = vec![false; n];
    let max_deg = adj.iter().map(Vec::len).max().unwrap_or(0);
    let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); max_deg + 1];
    for i in (0..n).rev() {
        buckets[adj[i].len()].push(i as u32);
    }
    let mut low = 0;
    let mut order = Vec::with_capacity(n);
    let mut merged: Vec<u32> = Vec::new();
    while order.len() < n {
        let v = loop {
            match buckets[low].pop() {
                Some(v) if !eliminated[v as usize] && adj[v as usize].len() == low => {
                    break v as usize;
                }
                Some(_) => {}
                None => low += 1,
            }
        };
        eliminated[v] = true;
        order.push(v);
        let nb = std::mem::take(&mut adj[v]);
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
                buckets.resize(d + 1, Vec::new());
            }
            buckets[d].push(u as u32);
            low = low.min(d);
        }
    }
    order
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
}
