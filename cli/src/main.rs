//! `daec`: the command line of the DAE compiler.
fn main() {}
