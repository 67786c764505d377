#!/usr/bin/env bash
# The table of docs/cli.md ("daec run FILE --t-end T --eps E"): the online design (the
# default, mu searched for during the run), the same with --mu-search off, and the
# pilot design, each from --t-end and --eps alone.
# Run from the repository root after `cargo build --release -p daec`.
set -u
D=target/release/daec
M=examples/models
H=docs/default-path
row() {
    local name=$1
    shift
    for design in "online" "online --mu-search off" "pilot"; do
        local start end out code
        start=$(date +%s.%N)
        # shellcheck disable=SC2086 # the design's words are flags
        out=$(timeout 120 "$D" run "$@" --design $design 2>&1)
        code=$?
        end=$(date +%s.%N)
        printf '%s | %s | exit %s | %.2f s | %s | max |s|/eps %s\n' "$name" "$design" "$code" \
            "$(echo "$end - $start" | bc)" \
            "$(echo "$out" | grep -oE '[0-9]+ updates' | head -1)" \
            "$(echo "$out" | grep -oE '\(([0-9.]+) eps\)' | tr -d '()eps ' | sort -g | tail -1)"
    done
}
row "four-bar, 2 s, eps 1e-3" $H/four_bar.dae --t-end 2 --eps 1e-3
row "slider-crank, 2 s, eps 1e-3" $H/slider_crank.dae --t-end 2 --eps 1e-3
row "rope N=50 hanging at rest, 1 s, eps 1e-3" $H/hanging_rope.dae --t-end 1 --eps 1e-3
row "chain N=20, end 1800x, 1 s, eps 1e-3" $M/chain.dae --set N=20 --set m_end=1800 --t-end 1 --eps 1e-3
row "chain N=100, end 10x, 0.5 s, eps 1e-3" $M/chain.dae --set N=100 --set m_end=10 --t-end 0.5 --eps 1e-3
row "double pendulum 3-D, 10 s, eps 0.2" $M/double_pendulum_3d.dae --t-end 10 --eps 0.2
row "double pendulum 3-D, 10 s, eps 1e-3" $M/double_pendulum_3d.dae --t-end 10 --eps 1e-3
row "hair S=4 N=8, 1 s, eps 1e-3" $M/hair.dae --set S=4 --set N=8 --t-end 1 --eps 1e-3
row "cloth W=16, 1 s, eps 6.67e-4" $M/cloth.dae --set W=16 --t-end 1 --eps 6.67e-4
row "hair of unequal strands (12 x 16), 1 s, eps 1e-4" $H/unequal_hair.dae --t-end 1 --eps 1e-4
row "triangle ribbon N=20 (80 links), 1 s, eps 1e-3" $H/triangle_ribbon.dae --t-end 1 --eps 1e-3
