// The published reference solutions of the Test Set for IVP Solvers (Mazzia and
// Magherini, release 2.4) for the models of this directory, included by the tests
// (`cli/tests/ivp_testset.rs`) and the benchmark (`bench/examples/ivp_testset.rs`).

/// The car axis problem's positions `xl, yl, xr, yr` at t = 3 (the test set's reference
/// solution, `y(1..4)`).
const CAR_AXIS_AT_3: [f64; 4] = [
    0.4934557842755629e-1,
    0.4969894602303324,
    1.0417425248854,
    0.3739110272652214,
];

/// Andrews' squeezing mechanism's angles at t = 0.03 (the test set's reference
/// solution, `y(1..7)`, computed by PSIDE with tolerances 1e-14).
const ANDREWS_AT_003: [f64; 7] = [
    0.1581077119629904e+2,
    -0.1575637105984298e+2,
    0.4082224013073101e-1,
    -0.5347301163226948,
    0.5244099658805304,
    0.5347301163226948,
    0.1048080741042263e+1,
];

/// The slider crank's coordinates at t = 0.1 (the test set's reference solution,
/// `y(1..7)`, computed by MEBDFI with tolerances 1e-14): the rigid `p1, p2, x3`, then
/// the rod's elastic coordinates `q1 .. q4` (metres, of order 1e-5).
const SLIDER_CRANK_AT_01: [f64; 7] = [
    0.1500000000000104e+2,
    -0.331173498825626,
    0.169737332842786,
    0.1893192899613509e-3,
    0.2375751249879174e-4,
    -0.5323896770569702e-5,
    -0.8363313279112129e-5,
];
