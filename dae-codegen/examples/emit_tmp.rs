fn main() {
    let path = std::env::args().nth(1).unwrap();
    let src = std::fs::read_to_string(&path).unwrap();
    let ms = dae_lang::compile_source(&src).unwrap();
    for m in &ms {
        print!("{}", dae_codegen::emit_rust(m));
    }
}
