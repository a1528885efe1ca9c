#!/usr/bin/env bash
# Instructions per message of each codec, counted by valgrind's callgrind: unlike timings,
# these do not move with the load of a shared machine.
#
#   bash codec/bench/callgrind.sh                   # no-alloc build of ours
#   bash codec/bench/callgrind.sh --features alloc  # alloc build (adds ours_decode_by_value)
#
# Each case runs `target/release/loop ROW CASE N` at N=N1 and N=N2; the difference of the
# totals over N2-N1 is the count for one message, without the setup (loading the frames,
# building the kept value). Output: a Markdown table; the callgrind files are kept in
# $OUT (default /tmp/j2735-callgrind) for callgrind_annotate.
set -euo pipefail
bench=$(cd "$(dirname "$0")" && pwd)
features=("$@")
N1=${N1:-10}
N2=${N2:-110}
out=${OUT:-/tmp/j2735-callgrind}
mkdir -p "$out"
command -v valgrind >/dev/null || { echo "valgrind is needed (apt-get install valgrind)" >&2; exit 1; }

target=${CARGO_TARGET_DIR:-$bench/target}
bin=$target/release/loop
# NO_BUILD=1 uses the loop binary as it is (built with the same features).
[[ ${NO_BUILD:-0} == 1 ]] || cargo build --release -j2 --manifest-path "$bench/Cargo.toml" --bin loop "${features[@]}" >&2

alloc=0
[[ " ${features[*]} " == *" alloc "* || " ${features[*]} " == *"--features=alloc"* ]] && alloc=1
rows=(bsm_001 spat_032 map_052 tim_222 tim_036 map_056 map_061)
cases=(ours_decode_into ours_decode_message_into ours_decoder_alternating ours_encode rasn_decode rasn_decode_alternating rasn_encode)
[[ $alloc == 1 ]] && cases=(ours_decode_into ours_decode_message_into ours_decode_by_value ours_decoder_alternating ours_encode rasn_decode rasn_decode_alternating rasn_encode)
suffix=""
[[ $alloc == 1 ]] && suffix="_alloc"

ir() { # row case n -> total instructions
  local f="$out/$1.$2$suffix.$3.out"
  valgrind --tool=callgrind --callgrind-out-file="$f" "$bin" "$1" "$2" "$3" 2>&1 >/dev/null \
    | sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}

declare -A per
for row in "${rows[@]}"; do
  for c in "${cases[@]}"; do
    a=$(ir "$row" "$c" "$N1")
    b=$(ir "$row" "$c" "$N2")
    per[$row.$c]=$(( (b - a) / (N2 - N1) ))
    echo "$row $c: ${per[$row.$c]} instructions/message" >&2
  done
done

echo "| frame | operation | ours instr/msg | rasn instr/msg | ours/rasn |"
echo "| --- | --- | ---: | ---: | ---: |"
for row in "${rows[@]}"; do
  for c in "${cases[@]}"; do
    case $c in
      ours_encode) r=rasn_encode ;;
      ours_decoder_alternating) r=rasn_decode_alternating ;;
      ours_*) r=rasn_decode ;;
      *) continue ;;
    esac
    o=${per[$row.$c]}
    t=${per[$row.$r]}
    ratio=$(awk -v o="$o" -v t="$t" 'BEGIN { printf "%.3f", o / t }')
    echo "| $row | ${c#ours_}$suffix | $o | $t | $ratio |"
  done
done
