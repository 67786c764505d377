//! Snapshots of the template derivations of the family examples (`daec derive` of a
//! family model prints `Analysis::derive_text`): one equation a line, the same for any
//! sizes, `J_Omega` as kernels with the conditions they hold in. Review a changed
//! snapshot with `cargo insta review`.

use dae_lang::{AnalysisOptions, analyze};
use dae_tests::models_dir;

const FAMILY_EXAMPLES: [&str; 5] = [
    "chain",
    "chain5_family",
    "cloth",
    "double_pendulum_family",
    "hair",
];

#[test]
fn template_text_of_every_family_example() {
    for stem in FAMILY_EXAMPLES {
        let path = models_dir().join(format!("{stem}.dae"));
        let src = std::fs::read_to_string(&path).expect("example model");
        let models = dae_lang::check_source(&src).unwrap_or_else(|e| panic!("{stem}: {e:?}"));
        let a = analyze(&models[0], &AnalysisOptions::default())
            .unwrap_or_else(|e| panic!("{stem}: {e:?}"));
        let text = a.derive_text();
        // Templates: one J line per coupling, each with its condition.
        let kernels: Vec<&str> = text.lines().filter(|l| l.starts_with("J(")).collect();
        assert!(!kernels.is_empty(), "{stem}: no kernel");
        assert!(
            kernels.iter().all(|l| l.contains(" when ")),
            "{stem}: {kernels:?}"
        );
        insta::assert_snapshot!(format!("family_{stem}"), text);
    }
}

#[test]
fn the_examples_with_families_are_all_snapshotted() {
    let families: Vec<String> = dae_tests::example_sources()
        .into_iter()
        .filter(|(_, text)| dae_lang::check_source(text).is_ok_and(|ms| ms[0].is_family()))
        .map(|(stem, _)| stem)
        .collect();
    assert_eq!(
        families, FAMILY_EXAMPLES,
        "a new family example: add it above"
    );
}
