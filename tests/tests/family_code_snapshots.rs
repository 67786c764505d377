//! The generated Rust of the family chain (`daec emit examples/models/chain.dae`):
//! the loops over links and particles with their gathers and scatter-adds, the entry
//! loops of `J_Omega`, the construction data. The same code for every size: review a
//! changed snapshot as you would review code.

#[test]
fn generated_code_of_the_family_chain() {
    let path = dae_tests::models_dir().join("chain.dae");
    let text = std::fs::read_to_string(path).expect("chain.dae");
    let models = dae_lang::compile_source(&text).expect("chain compiles");
    insta::assert_snapshot!("family_chain_code", dae_codegen::emit_rust(&models[0]));
}
