// The Rust that `daec emit` prints for `tests/ui/names.dae` (models and parameters named
// like Rust keywords, primitive and prelude types and traits, and names the generated
// code uses) compiles, keeps every parameter as its own field, and leaves the prelude
// usable next to it. `tests/tests/trybuild.rs` writes the file and names it in
// `DAE_EMITTED_NAMES`.
use dae_runtime::Model;

include!(env!("DAE_EMITTED_NAMES"));

fn main() {
    // `type` and `type_` are two fields (the mangling is injective), `_` and `Self` too.
    let mut m = Self_::default();
    assert_eq!((m.type_, m.type__, m.type___), (1.0, 2.0, 3.0));
    assert_eq!((m.__, m.___, m.self_, m.Self_), (4.0, 5.0, 6.0, 7.0));
    assert_eq!((m.f64_, m.Default_), (0.0, -1.5));
    assert_eq!(m.name(), "Self");
    assert_eq!(m.param_name(1), "type_");
    m.set_param(1, 9.0);
    assert_eq!(m.type__, 9.0);
    assert_eq!(m.indices(), &[3]);
    // Models named `Self`, `Self_` and `Self__` are three types.
    assert_eq!(Self__::default().name(), "Self_");
    assert_eq!(Self___::default().name(), "Self__");
    let f = f64_::default();
    assert_eq!((f.usize_, f.str_, f.f64_, f.x), (2.0, 1.0, 3.0, 1.0));
    let mut dx = [0.0];
    f.rhs(0.0, &[1.0], &[], &mut dx);
    assert_eq!(dx, [-6.0]);
    let names = [
        f64__::default().name().to_string(),
        usize_::default().name().to_string(),
        Model_::default().name().to_string(),
        Default_::default().name().to_string(),
        core_::default().name().to_string(),
        std_::default().name().to_string(),
        dae_runtime_::default().name().to_string(),
        Vec_::default().name().to_string(),
        Option_::default().name().to_string(),
        Some_::default().name().to_string(),
        TryInto_::default().name().to_string(),
        String_::default().name().to_string(),
        Clone_::default().name().to_string(),
        x::default().name().to_string(),
        v0::default().name().to_string(),
        crate_::default().name().to_string(),
        super_::default().name().to_string(),
        async_::default().name().to_string(),
    ];
    // The prelude is untouched by the generated types.
    let joined: Vec<String> = names.iter().map(|n| n.clone()).collect();
    let first: Option<&String> = joined.first();
    assert_eq!(first.map(String::as_str), Some("f64_"));
    assert_eq!(joined.len(), 18);
}
