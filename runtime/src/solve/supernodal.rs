//! Multifrontal `LDL^T` on fundamental supernodes (Duff and Reid 1983; Liu, SIAM
//! Review 34, 1992), the numeric kernel of the sparse solver for symmetric values.
//!
//! Columns with the same row structure that follow each other up the elimination tree
//! form a supernode; each supernode is factored in a dense frontal matrix that gathers
//! its entries of `J_Omega` and its children's update matrices (extend-add), eliminates
//! its own columns with dense column operations (contiguous, vectorised) and passes the
//! Schur complement to its parent on a stack. All index maps are built once per
//! pattern; a factorisation allocates nothing. On cloth (mesh-like patterns) this is
//! several times faster than the up-looking scalar kernel, which the sparse solver
//! keeps for unsymmetric values and for diagnosing a failed pivot.

use super::structure::NONE;

#[derive(Clone)]
pub(crate) struct Supernodal {
    /// Supernodes in postorder: first column, number of pivot columns, front size,
    /// offset of their rows in `rows` and of their factor block in `lval`.
    nodes: Vec<Node>,
    /// Row structure of each supernode: its own columns, then the rows below.
    rows: Vec<u32>,
    /// Per supernode: `(front position, entry)` of the entries of `J_Omega` it gathers.
    assembly_ptr: Vec<usize>,
    assembly: Vec<(u32, u32)>,
    /// Per supernode: positions of each child's update rows in its front, children in
    /// the order their update matrices sit on the stack (last pushed first).
    rel_ptr: Vec<usize>,
    rel: Vec<u32>,
    children_ptr: Vec<usize>,
    /// Factor blocks (`nf x ns`, column-major) and the diagonal `D` (permuted order).
    lval: Vec<f64>,
    pub(crate) d: Vec<f64>,
    front: Vec<f64>,
    stack: Vec<f64>,
}

#[derive(Clone, Copy)]
struct Node {
    first: usize,
    ns: usize,
    nf: usize,
    rows: usize,
    lval: usize,
}

impl Supernodal {
    /// `parent`: elimination tree; `col_ptr`/`row_idx`: strictly lower `L` (CSC, rows
    /// ascending); `lower[tri_ptr[k]..tri_ptr[k+1]]`: entries `A[k, j]`, `j < k`;
    /// `diag[k]`: entry of `A[k, k]` (`NONE` if absent). All in permuted numbering.
    pub(crate) fn new(
        parent: &[usize],
        col_ptr: &[usize],
        row_idx: &[usize],
        lower: &[(u32, u32)],
        tri_ptr: &[usize],
        diag: &[usize],
    ) -> Self {
        let n = parent.len();
        let count = |j: usize| col_ptr[j + 1] - col_ptr[j];
        let mut kids = vec![0usize; n];
        for &p in parent {
            if p != NONE {
                kids[p] += 1;
            }
        }
        // Fundamental supernodes: j joins j-1's when j-1's only parent is j, j has no
        // other child, and their structures agree.
        let mut first_of = Vec::new();
        let mut snode = vec![0usize; n];
        for j in 0..n {
            let joins = j > 0 && parent[j - 1] == j && kids[j] == 1 && count(j - 1) == count(j) + 1;
            if !joins {
                first_of.push(j);
            }
            snode[j] = first_of.len() - 1;
        }
        let ns_total = first_of.len();
        first_of.push(n);
        let last = |s: usize| first_of[s + 1] - 1;
        let sparent: Vec<usize> = (0..ns_total)
            .map(|s| {
                let p = parent[last(s)];
                if p == NONE { NONE } else { snode[p] }
            })
            .collect();
        // Postorder of the supernodal tree (children in ascending order).
        let mut child_lists: Vec<Vec<usize>> = vec![Vec::new(); ns_total];
        let mut roots = Vec::new();
        for (s, &p) in sparent.iter().enumerate() {
            match p {
                NONE => roots.push(s),
                p => child_lists[p].push(s),
            }
        }
        let mut post = Vec::with_capacity(ns_total);
        let mut todo: Vec<(usize, usize)> = roots.iter().rev().map(|&r| (r, 0)).collect();
        while let Some((s, next)) = todo.pop() {
            if next < child_lists[s].len() {
                todo.push((s, next + 1));
                todo.push((child_lists[s][next], 0));
            } else {
                post.push(s);
            }
        }
        // Row structures, fronts, factor blocks.
        let mut nodes = Vec::with_capacity(ns_total);
        let mut rows: Vec<u32> = Vec::new();
        let mut local = vec![0u32; n];
        let mut index_of = vec![NONE; ns_total];
        let mut lsize = 0;
        let mut max_front = 0;
        for &s in &post {
            let (f, l) = (first_of[s], last(s));
            let start = rows.len();
            rows.extend((f..=l).map(|j| j as u32));
            rows.extend(
                row_idx[col_ptr[l]..col_ptr[l + 1]]
                    .iter()
                    .map(|&r| r as u32),
            );
            let nf = rows.len() - start;
            let ns = l - f + 1;
            index_of[s] = nodes.len();
            nodes.push(Node {
                first: f,
                ns,
                nf,
                rows: start,
                lval: lsize,
            });
            lsize += nf * ns;
            max_front = max_front.max(nf);
        }
        // Assembly lists and extend-add maps; the stack's peak size by simulation.
        let mut assembly_ptr = vec![0];
        let mut assembly = Vec::new();
        let mut rel_ptr = vec![0];
        let mut rel = Vec::new();
        let mut children_ptr = vec![0];
        let mut stack_sizes: Vec<usize> = Vec::new();
        let (mut depth, mut peak) = (0usize, 0usize);
        for node in &nodes {
            let r = &rows[node.rows..node.rows + node.nf];
            for (i, &row) in r.iter().enumerate() {
                local[row as usize] = i as u32;
            }
            let nf = node.nf;
            for c in 0..node.ns {
                let k = node.first + c;
                if diag[k] != NONE {
                    assembly.push(((c * nf + c) as u32, diag[k] as u32));
                }
            }
            // Entries A[k, j] with j a column of this supernode, k > j: rows k of the
            // structure. Walk the rows of the structure and pick entries in our columns.
            for &row in r {
                let k = row as usize;
                for &(j, e) in &lower[tri_ptr[k]..tri_ptr[k + 1]] {
                    let j = j as usize;
                    if j >= node.first && j < node.first + node.ns && e != u32::MAX {
                        let (ci, ri) = (j - node.first, local[k] as usize);
                        assembly.push(((ci * nf + ri) as u32, e));
                    }
                }
            }
            assembly_ptr.push(assembly.len());
            // Children's update matrices are the last `kids` on the stack, popped in
            // reverse postorder.
            let s = snode[node.first];
            for &c in child_lists[s].iter().rev() {
                let cn = nodes[index_of[c]];
                let crow = &rows[cn.rows + cn.ns..cn.rows + cn.nf];
                rel.extend(crow.iter().map(|&row| local[row as usize]));
                rel_ptr.push(rel.len());
                let u = stack_sizes.pop().expect("child update on the stack");
                depth -= u;
            }
            children_ptr.push(rel_ptr.len() - 1);
            let u = (nf - node.ns) * (nf - node.ns);
            stack_sizes.push(u);
            depth += u;
            peak = peak.max(depth);
        }
        Self {
            nodes,
            rows,
            assembly_ptr,
            assembly,
            rel_ptr,
            rel,
            children_ptr,
            lval: vec![0.0; lsize],
            d: vec![0.0; n],
            front: vec![0.0; max_front * max_front],
            stack: Vec::with_capacity(peak),
        }
    }

    /// The pivots `D` of the last factorisation (permuted order).
    pub(crate) fn pivots(&self) -> &[f64] {
        &self.d
    }

    /// Values stored by the factor (blocks and diagonal).
    pub(crate) fn stored_values(&self) -> usize {
        self.lval.len() + self.d.len()
    }

    /// Factor; `Err(k)` names the permuted column whose pivot was below `tol`.
    pub(crate) fn factor(&mut self, values: &[f64], tol: f64) -> Result<(), usize> {
        self.stack.clear();
        for (s, node) in self.nodes.iter().enumerate() {
            let (nf, ns) = (node.nf, node.ns);
            let f = &mut self.front[..nf * nf];
            f.fill(0.0);
            for &(pos, e) in &self.assembly[self.assembly_ptr[s]..self.assembly_ptr[s + 1]] {
                f[pos as usize] += values[e as usize];
            }
            for c in self.children_ptr[s]..self.children_ptr[s + 1] {
                let rel = &self.rel[self.rel_ptr[c]..self.rel_ptr[c + 1]];
                let u = rel.len();
                let top = self.stack.len() - u * u;
                let upd = &self.stack[top..];
                for jj in 0..u {
                    let col = rel[jj] as usize * nf;
                    for ii in jj..u {
                        f[col + rel[ii] as usize] += upd[jj * u + ii];
                    }
                }
                self.stack.truncate(top);
            }
            for k in 0..ns {
                let dk = f[k * nf + k];
                if dk.abs() <= tol || dk.is_nan() {
                    return Err(node.first + k);
                }
                self.d[node.first + k] = dk;
                let (head, tail) = f.split_at_mut((k + 1) * nf);
                let colk = &mut head[k * nf..];
                for j in k + 1..nf {
                    let c = colk[j] / dk;
                    if c != 0.0 {
                        let colj = &mut tail[(j - k - 1) * nf + j..(j - k) * nf];
                        for (x, w) in colj.iter_mut().zip(&colk[j..]) {
                            *x -= c * w;
                        }
                    }
                }
                for x in &mut colk[k + 1..] {
                    *x /= dk;
                }
            }
            let block = &mut self.lval[node.lval..node.lval + nf * ns];
            for k in 0..ns {
                block[k * nf..(k + 1) * nf].copy_from_slice(&f[k * nf..(k + 1) * nf]);
            }
            // The update matrix, square u x u: column jj holds rows ns.. of front
            // column ns + jj (the part above the diagonal is unused).
            for jj in ns..nf {
                self.stack
                    .extend_from_slice(&f[jj * nf + ns..(jj + 1) * nf]);
            }
        }
        Ok(())
    }

    /// `x <- (L D L^T)^{-1} x` in permuted numbering.
    pub(crate) fn solve(&self, x: &mut [f64]) {
        for node in &self.nodes {
            let rows = &self.rows[node.rows..node.rows + node.nf];
            let block = &self.lval[node.lval..node.lval + node.nf * node.ns];
            for k in 0..node.ns {
                let xk = x[node.first + k];
                if xk != 0.0 {
                    let col = &block[k * node.nf..(k + 1) * node.nf];
                    for i in k + 1..node.nf {
                        x[rows[i] as usize] -= col[i] * xk;
                    }
                }
            }
        }
        for (xi, d) in x.iter_mut().zip(&self.d) {
            *xi /= d;
        }
        for node in self.nodes.iter().rev() {
            let rows = &self.rows[node.rows..node.rows + node.nf];
            let block = &self.lval[node.lval..node.lval + node.nf * node.ns];
            for k in (0..node.ns).rev() {
                let col = &block[k * node.nf..(k + 1) * node.nf];
                let mut s = x[node.first + k];
                for i in k + 1..node.nf {
                    s -= col[i] * x[rows[i] as usize];
                }
                x[node.first + k] = s;
            }
        }
    }
}
