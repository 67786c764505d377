fn main() {
    let path = std::env::args().nth(1).expect("a .dae file");
    let src = std::fs::read_to_string(&path).unwrap();
    match dae_lang::analyze_source(&src) {
        Ok(ms) => {
            for (_, a) in ms {
                print!("{}", a.derive_text());
            }
        }
        Err(ds) => {
            for d in ds {
                eprint!("{}", d.render(&path, &src, false));
            }
        }
    }
}
