use super::fixtures::*;
use super::*;

#[test]
fn smoke_double_pendulum() {
    let a = analyze(&double_pendulum_3d(), &AnalysisOptions::default()).unwrap();
    println!("{}", a.derive_text());
    println!("{:?} {}", a.jacobian_at_initial, a.condition_number);
}
