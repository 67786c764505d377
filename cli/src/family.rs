//! Family models (language version 2) on the command line: the values of `--set
//! NAME=VALUE`, the topology file of `--topology`, the model that `daec run` simulates
//! (a sized family instance run by the interpreter, or a version-1 model with its
//! parameters set), and the part of `daec check` that builds a family model at its
//! default sizes.
//!
//! # The topology file
//!
//! Sets declared without a size (`set P;`) and maps declared without a formula
//! (`map a[l in L] -> P;`) are given when the model is built, by a text file:
//!
//! ```text
//! # a star: particle 0 in the middle, four links
//! set P 5            # the size of a set declared `set P;`
//! edges L: a b       # the lines below are the elements of L, in order: a[l] b[l]
//! 0 1
//! 0 2
//! 0 3
//! 0 4
//! ```
//!
//! `set NAME SIZE` gives a set's size. `edges SET: MAP ...` starts a block: each line up
//! to the next `set`/`edges` line (or the end) is one element of `SET` (0, 1, ...) with
//! its value under each named map, whose domain must be `SET`. A set given at
//! construction without a `set` line gets the number of lines of its block as its size.
//! Elements count from 0; `#` starts a comment; blank lines are ignored.

use std::path::Path;

use crate::redundant::Redundant;
use crate::{Reported, source};
use dae_lang::CompiledModel;
use dae_lang::family::{AssignError, Construction, Spec};
use dae_lang::model::MapKind;
use dae_runtime::Model;
use dae_runtime::family::{FamilyInstance, Interpreter, Kernels};

/// `NAME=VALUE` of `--set` (the clap value parser).
pub(crate) fn parse_assignment(text: &str) -> Result<(String, f64), String> {
    let Some((name, value)) = text.split_once('=') else {
        return Err(format!(
            "`{text}` is not NAME=VALUE (e.g. --set N=1000 --set m_end=10)"
        ));
    };
    let name = name.trim();
    if name.is_empty() {
        return Err(format!("`{text}` has no name before `=`"));
    }
    match value.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok((name.to_string(), v)),
        _ => Err(format!(
            "`{}` in `{text}` is not a finite number",
            value.trim()
        )),
    }
}

/// A topology file, read and checked against its own syntax.
#[derive(Debug, Default)]
pub(crate) struct Topology {
    /// The file's display name.
    name: String,
    /// `set NAME SIZE` lines: name, size, line.
    sets: Vec<(String, usize, usize)>,
    /// Edge blocks: the domain set, its line, and per map its name and values.
    blocks: Vec<Block>,
}

#[derive(Debug)]
struct Block {
    set: String,
    line: usize,
    maps: Vec<String>,
    /// One row per element: the values and the line.
    rows: Vec<(Vec<u32>, usize)>,
}

fn topo_error(file: &str, line: usize, what: &str, hint: &str) -> Reported {
    error!("{file}:{line}: {what}\n  hint: {hint}");
    Reported
}

/// Reads a topology file (format in the module documentation).
pub(crate) fn read_topology(path: &Path) -> Result<Topology, Reported> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| {
        error!("cannot read the topology file `{name}`: {e}");
        Reported
    })?;
    let mut t = Topology {
        name: name.clone(),
        ..Topology::default()
    };
    let syntax = "a line is `set NAME SIZE`, `edges SET: MAP ...`, or the values of one element under the maps of its block";
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let mut words = content.split_whitespace();
        match words.next() {
            Some("set") => {
                let (Some(set), Some(size), None) = (words.next(), words.next(), words.next())
                else {
                    return Err(topo_error(&name, line, "expected `set NAME SIZE`", syntax));
                };
                let Ok(size) = size.parse::<usize>() else {
                    return Err(topo_error(
                        &name,
                        line,
                        &format!("the size of set `{set}` is `{size}`, not a whole number"),
                        "a set's size is a whole number of elements",
                    ));
                };
                if t.sets.iter().any(|s| s.0 == set) {
                    return Err(topo_error(
                        &name,
                        line,
                        &format!("set `{set}` is given twice"),
                        "give each set's size once",
                    ));
                }
                t.sets.push((set.to_string(), size, line));
            }
            Some("edges") => {
                let rest = content["edges".len()..].trim();
                let Some((set, maps)) = rest.split_once(':') else {
                    return Err(topo_error(
                        &name,
                        line,
                        "expected `edges SET: MAP ...`",
                        syntax,
                    ));
                };
                let maps: Vec<String> = maps.split_whitespace().map(str::to_string).collect();
                let set = set.trim().to_string();
                if maps.is_empty() || set.is_empty() || set.contains(char::is_whitespace) {
                    return Err(topo_error(
                        &name,
                        line,
                        "expected `edges SET: MAP ...` with one set and at least one map",
                        syntax,
                    ));
                }
                for m in &maps {
                    if t.blocks.iter().any(|b| b.maps.contains(m)) {
                        return Err(topo_error(
                            &name,
                            line,
                            &format!("map `{m}` is given twice"),
                            "give each map in one block",
                        ));
                    }
                }
                t.blocks.push(Block {
                    set,
                    line,
                    maps,
                    rows: Vec::new(),
                });
            }
            Some(_) => {
                let Some(block) = t.blocks.last_mut() else {
                    return Err(topo_error(
                        &name,
                        line,
                        &format!("`{content}` before any `edges` line"),
                        syntax,
                    ));
                };
                let mut values = Vec::with_capacity(block.maps.len());
                for w in content.split_whitespace() {
                    match w.parse::<u32>() {
                        Ok(v) => values.push(v),
                        Err(_) => {
                            return Err(topo_error(
                                &name,
                                line,
                                &format!("`{w}` is not an element (a whole number from 0)"),
                                syntax,
                            ));
                        }
                    }
                }
                if values.len() != block.maps.len() {
                    return Err(topo_error(
                        &name,
                        line,
                        &format!(
                            "{} values, but the block of line {} gives {} map{} ({})",
                            values.len(),
                            block.line,
                            block.maps.len(),
                            if block.maps.len() == 1 { "" } else { "s" },
                            block.maps.join(" ")
                        ),
                        "give one value per map on every line of the block",
                    ));
                }
                block.rows.push((values, line));
            }
            None => {}
        }
    }
    Ok(t)
}

impl Topology {
    /// Adds the sets and maps of the file to `spec`, checked against the model: every
    /// set named is declared `set NAME;`, every map named is declared without a formula
    /// on the block's set, and each value lies inside its codomain when that set's size
    /// is given here (the others are checked at construction).
    fn apply(&self, c: &Construction, spec: &mut Spec) -> Result<(), Reported> {
        let given_sets: Vec<&str> = c
            .sets
            .iter()
            .filter(|s| s.size.is_none())
            .map(|s| s.name.as_str())
            .collect();
        let given_maps: Vec<&str> = c
            .maps
            .iter()
            .filter(|m| m.kind == MapKind::Given)
            .map(|m| m.name.as_str())
            .collect();
        let list = |v: &[&str]| {
            if v.is_empty() {
                "none".to_string()
            } else {
                v.join(", ")
            }
        };
        let set_hint = format!(
            "the sets given at construction are declared `set NAME;` (this model: {})",
            list(&given_sets)
        );
        for (set, size, line) in &self.sets {
            if !given_sets.contains(&set.as_str()) {
                return Err(topo_error(
                    &self.name,
                    *line,
                    &format!("the model has no set `{set}` given at construction"),
                    &set_hint,
                ));
            }
            spec.sets.push((set.clone(), *size));
        }
        let size_of = |set: &str, spec: &Spec| spec.sets.iter().find(|s| s.0 == set).map(|s| s.1);
        for b in &self.blocks {
            let Some(dom) = c.sets.iter().position(|s| s.name == b.set) else {
                return Err(topo_error(
                    &self.name,
                    b.line,
                    &format!("the model has no set `{}`", b.set),
                    &format!(
                        "the model's sets: {}",
                        c.sets
                            .iter()
                            .map(|s| s.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ));
            };
            if c.sets[dom].size.is_none() && size_of(&b.set, spec).is_none() {
                spec.sets.push((b.set.clone(), b.rows.len()));
            }
            for (k, m) in b.maps.iter().enumerate() {
                let def = c
                    .maps
                    .iter()
                    .find(|d| &d.name == m && d.kind == MapKind::Given)
                    .ok_or_else(|| {
                        topo_error(
                            &self.name,
                            b.line,
                            &format!("the model has no map `{m}` given at construction"),
                            &format!(
                                "the maps given at construction are declared without a formula (this model: {})",
                                list(&given_maps)
                            ),
                        )
                    })?;
                if def.domain.map(|s| s.index()) != Some(dom) {
                    let declared = def
                        .domain
                        .map_or("the unit".to_string(), |s| c.sets[s.index()].name.clone());
                    return Err(topo_error(
                        &self.name,
                        b.line,
                        &format!("map `{m}` is declared over `{declared}`, not `{}`", b.set),
                        &format!("give `{m}` in an `edges {declared}: ...` block"),
                    ));
                }
                let codomain = def.codomain.map(|s| c.sets[s.index()].name.as_str());
                let bound = codomain.and_then(|s| size_of(s, spec));
                let values: Vec<u32> = b.rows.iter().map(|r| r.0[k]).collect();
                if let (Some(n), Some(cod)) = (bound, codomain) {
                    if let Some((e, (row, line))) = b
                        .rows
                        .iter()
                        .enumerate()
                        .find(|(_, r)| r.0[k] as usize >= n)
                    {
                        return Err(topo_error(
                            &self.name,
                            *line,
                            &format!(
                                "map `{m}` points outside its set: element {e} of `{}` goes to {}, but `{cod}` has {n} elements (0..{n})",
                                b.set, row[k]
                            ),
                            "elements count from 0: check the edge list against the set sizes",
                        ));
                    }
                }
                spec.maps.push((m.clone(), values));
            }
        }
        Ok(())
    }
}

/// The construction spec of `--set` values and a topology: sizes (whole numbers) and
/// scalar parameters by name; anything else is an error naming what can be set.
pub(crate) fn spec_for(
    c: &Construction,
    sets: &[(String, f64)],
    topology: Option<&Topology>,
) -> Result<Spec, Reported> {
    let mut spec = Spec::default();
    for (name, value) in sets {
        match spec.assign(c, name, *value) {
            Ok(()) => {}
            Err(AssignError::NotWhole) => {
                error!(
                    "--set {name}={value}: `{name}` is a size, a whole number >= 0\n  hint: e.g. --set {name}=1000"
                );
                return Err(Reported);
            }
            Err(AssignError::PerElement(family)) => {
                error!(
                    "--set {name}={value}: `{family}` is a per-element parameter (one value per element of its set)\n  hint: change the formula of its declaration, or set its elements through the runtime API (`set_param_named(\"{family}[3]\", ..)`)",
                );
                return Err(Reported);
            }
            Err(AssignError::Unknown) => {
                error!(
                    "--set {name}={value}: the model has no size or scalar parameter `{name}`\n  hint: {}",
                    settable(c)
                );
                return Err(Reported);
            }
        }
    }
    if let Some(t) = topology {
        t.apply(c, &mut spec)?;
    }
    Ok(spec)
}

/// What `--set` accepts for a family model, for hints.
fn settable(c: &Construction) -> String {
    let sizes: Vec<&str> = c.sizes.iter().map(|s| s.name.as_str()).collect();
    let params: Vec<&str> = c
        .params
        .iter()
        .filter(|p| p.family.over.is_none())
        .map(|p| p.name.as_str())
        .collect();
    let list = |v: &[&str]| {
        if v.is_empty() {
            "none".to_string()
        } else {
            v.join(", ")
        }
    };
    format!(
        "--set takes the sizes ({}) and the scalar parameters ({})",
        list(&sizes),
        list(&params)
    )
}

/// The model `daec run` simulates: the compiled model of the file (the one it holds, or
/// `wanted`), a family model built at the `--set` sizes and parameters and the topology
/// (construction errors rendered with the source), or a version-1 model with its
/// parameters set by `--set`.
pub(crate) fn runnable(
    path: &Path,
    wanted: Option<&str>,
    sets: &[(String, f64)],
    topology: Option<&Path>,
) -> Result<Box<dyn Model>, Reported> {
    let (name, src, compiled) = source::compiled(path, wanted)?;
    if !compiled.is_family() {
        if let Some(t) = topology {
            error!(
                "--topology {}: `{}` has no sets (a version-1 model); a topology gives the sets and maps of a family model",
                t.display(),
                compiled.name
            );
            return Err(Reported);
        }
        // Each `--set` replaces the value written in the declaration and the model is
        // checked and analysed again, so that the parameters whose defaults read it
        // follow (setting the field of a compiled parameter would leave them as they
        // were).
        let compiled = if sets.is_empty() {
            compiled
        } else {
            let (_, analysis) = crate::check_set::analysed(&name, &src, wanted, sets)?
                .pop()
                .expect("one model");
            dae_lang::compile(&analysis)
        };
        let model = dae_runtime::family::Interpreted::from_compiled(compiled, &Spec::default())
            .map_err(|e| source::report(&name, &src, &[e.to_diagnostic()]))?;
        return Ok(Box::new(model));
    }
    let topology = topology.map(read_topology).transpose()?;
    let kernels = Interpreter::new(compiled);
    let spec = spec_for(kernels.construction(), sets, topology.as_ref())?;
    let c = kernels.construction();
    let c_given: Vec<String> = c
        .sets
        .iter()
        .filter(|s| s.size.is_none())
        .map(|s| s.name.clone())
        .chain(
            c.maps
                .iter()
                .filter(|m| m.kind == MapKind::Given)
                .map(|m| m.name.clone()),
        )
        .collect();
    match FamilyInstance::interpreted(kernels, &spec) {
        Ok(m) => Ok(Box::new(m)),
        Err(e) => {
            let r = source::report(&name, &src, &[e.to_diagnostic()]);
            match &topology {
                Some(t) => note!(
                    "the sets and maps given at construction come from `{}`",
                    t.name
                ),
                None if !c_given.is_empty() => note!(
                    "`{}` {} given at construction: run the model with --topology FILE (the format is in docs/language.md, \"Topology files\")",
                    c_given.join("`, `"),
                    if c_given.len() == 1 { "is" } else { "are" }
                ),
                None => {}
            }
            Err(r)
        }
    }
}

/// What `daec check` says about a family model beyond its templates: the model built at
/// its default sizes (when it needs nothing given at run time), with the structural rank
/// of `J_Omega` (bipartite matching on the pattern) and a factorisation of its values at
/// the initial point by the solver `daec run` would choose.
#[derive(Debug, serde::Serialize)]
pub(crate) struct DefaultSizes {
    /// `N = 10, ...`.
    pub sizes: String,
    /// Whether the sizes or the topology were given (`daec check --set`, `--topology`).
    pub given: bool,
    pub states: usize,
    pub constraints: usize,
    pub entries: usize,
    pub structural_rank: usize,
    pub nonsingular: bool,
    pub solver: String,
}

/// The template header of a family model for `daec check`: the `sizes`, `sets` and
/// `maps` lines of the derivation and the cases of each `J_Omega` kernel (`J(link[l],
/// z[k])` with its `when` conditions), from the analysis's template text.
pub(crate) fn template_lines(derive_text: &str) -> (Vec<String>, Vec<(String, Vec<String>)>) {
    let mut header = Vec::new();
    let mut kernels: Vec<(String, Vec<String>)> = Vec::new();
    for line in derive_text.lines() {
        for key in ["sizes", "sets", "maps"] {
            if let Some(rest) = line.strip_prefix(&format!("// {key}: ")) {
                header.push(format!("{key}: {rest}"));
            }
        }
        if line.starts_with("J(") {
            let (lhs, rest) = line.split_once(" = ").unwrap_or((line, ""));
            let case = rest
                .rsplit_once("  when ")
                .map_or("always".to_string(), |(_, c)| c.to_string());
            match kernels.iter_mut().find(|k| k.0 == lhs) {
                Some(k) => k.1.push(case),
                None => kernels.push((lhs.to_string(), vec![case])),
            }
        }
    }
    (header, kernels)
}

/// Builds the model at its default sizes and checks `J_Omega` there (see
/// [`DefaultSizes`]); `None` when sets or maps are given at run time. A singular
/// `J_Omega` is an error naming the dependent constraints.
///
/// With a topology, the sets and maps it gives are used (and the model is built even when
/// it is not self-contained); `given` says that the sizes or the topology came from the
/// command line (`daec check --set`, `--topology`).
pub(crate) fn at_default_sizes(
    compiled: CompiledModel,
    topology: Option<&Topology>,
    given: bool,
    (file, src): (&str, &str),
) -> Result<Option<DefaultSizes>, Reported> {
    use dae_runtime::{solve::LinearSolver, solve::Solver, solve::SolverChoice};
    let name = compiled.name.clone();
    if !compiled.is_family() {
        return Ok(None);
    }
    let kernels = Interpreter::new(compiled);
    let c = kernels.construction();
    if !c.self_contained() && topology.is_none() {
        return Ok(None);
    }
    let spec = spec_for(c, &[], topology)?;
    let sizes = c
        .sizes
        .iter()
        .map(|s| format!("{} = {}", s.name, s.default))
        .collect::<Vec<_>>()
        .join(", ");
    let model = FamilyInstance::interpreted(kernels, &spec).map_err(|e| {
        match topology {
            Some(t) => error!(
                "`{name}` with the sets and maps of `{}`: {e}\n  hint: check the topology file against the model's sets and maps (docs/language.md, \"Topology files\")",
                t.name
            ),
            // The checker built the model at these sizes already; kept for completeness.
            None => error!("`{name}` at its sizes: {e}"),
        }
        Reported
    })?;
    let (n, m) = (model.n_states(), model.n_constraints());
    let pattern = model.jacobian_pattern();
    let rank = dae_runtime::family::structural_rank(m, pattern);
    let names = |rows: &[usize]| {
        let shown: Vec<&str> = rows
            .iter()
            .take(8)
            .map(|&r| model.constraint_name(r))
            .collect();
        let more = rows.len().saturating_sub(shown.len());
        format!(
            "{}{}",
            shown.join(", "),
            if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            }
        )
    };
    if rank.rank < m {
        error!(
            "J_Omega of `{name}` is structurally singular at the default sizes ({sizes}): structural rank {} of {m}; no algebraic unknown is left for {}\n  hint: each constraint needs its own algebraic unknown in its Omega (check the maps and the sums)",
            rank.rank,
            names(&rank.unmatched_rows)
        );
        return Err(Reported);
    }
    let mut x = vec![0.0; n];
    let mut z = vec![0.0; m];
    model.initial_state(&mut x);
    model.initial_alg(&mut z);
    let which = if given { "given" } else { "default" };
    let mut dx = vec![0.0; n];
    model.rhs(0.0, &x, &z, &mut dx);
    if let Some(k) = dx.iter().position(|v| !v.is_finite()) {
        error!(
            "the derivative of `{}` in `{name}` is {} at t = 0 with the {which} sizes ({sizes})\n  hint: an operation of its `der` item has no finite value at the start (a division by zero?), or a mass matrix it is listed in is singular there",
            model.state_name(k),
            dx[k]
        );
        return Err(Reported);
    }
    let mut values = vec![0.0; pattern.len()];
    model.jacobian(0.0, &x, &z, &mut values);
    let mut solver_name = String::new();
    let mut outcome = Err(dae_runtime::solve::SolveError::Pattern(String::new()));
    for choice in [SolverChoice::Auto, SolverChoice::Dense] {
        let mut solver = Solver::new(m, pattern, choice).map_err(|e| {
            error!("J_Omega of `{name}`: {e}");
            Reported
        })?;
        outcome = solver.factor(&values, &vec![1.0; m]);
        solver_name = solver.name().to_string();
        // Only a breakdown of an elimination without pivoting is worth a dense retry.
        if !matches!(
            outcome,
            Err(dae_runtime::solve::SolveError::Breakdown { .. })
        ) || m > 4096
        {
            break;
        }
    }
    match outcome {
        Ok(()) => Ok(Some(DefaultSizes {
            sizes,
            given,
            states: n,
            constraints: m,
            entries: pattern.len(),
            structural_rank: rank.rank,
            nonsingular: true,
            solver: solver_name,
        })),
        Err(dae_runtime::solve::SolveError::Singular { constraints }) => {
            let at = format!("t = 0 with the {which} sizes ({sizes})");
            match Redundant::at(&model, 0.0, &x, &z) {
                Some(r) => {
                    source::report(file, src, &[singular_diagnostic(&model, &name, &at, &r)]);
                }
                None => error!(
                    "J_Omega of `{name}` is singular at {at}: the rows of {} are dependent\n  hint: the algebraic unknowns do not determine these constraints at the initial point (a link of length zero? two links along one line at a particle with no other support?)",
                    names(&constraints)
                ),
            }
            Err(Reported)
        }
        Err(e) => {
            error!("J_Omega of `{name}` at t = 0 with the default sizes ({sizes}): {e}");
            Err(Reported)
        }
    }
}

/// A singular `J_Omega` of a family model at the model's lines: the first family with
/// implied constraints underlined, the others' counts beside their declarations, one
/// dependency written out in the hint.
fn singular_diagnostic(
    model: &FamilyInstance<Interpreter>,
    name: &str,
    at: &str,
    r: &Redundant,
) -> dae_lang::Diagnostic {
    let span_of = |family: &str| {
        model
            .kernels()
            .construction()
            .constraints
            .iter()
            .find(|c| c.name == family)
            .map_or(dae_lang::ast::Span::new(0, 0), |c| c.span)
    };
    let lines = r.family_lines(model);
    let main = r
        .families
        .iter()
        .position(|(_, _, implied)| !implied.is_empty())
        .unwrap_or(0);
    let related = lines
        .iter()
        .enumerate()
        .filter(|&(k, _)| k != main)
        .map(|(_, (family, text))| (span_of(family), text.clone()))
        .collect();
    dae_lang::Diagnostic {
        message: format!("J_Omega of `{name}` is singular at {at}: {}", r.counts()),
        span: span_of(&lines[main].0),
        label: lines[main].1.clone(),
        hint: Some(format!(
            "remove the implied constraints, or make them forces (rigid diagonals of a flat cloth are implied by its links in its plane), or start where they are independent; at this start {}",
            r.dependency(model)
        )),
        related,
    }
}
