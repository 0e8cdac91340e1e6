#!/bin/sh
# Issue 12's table: the dim room's mean (red channel; the lamps are white)
# with the bright room's lamp on over with it off (true ratio 1), per wall
# thickness and brightness ratio; one JSON object per case.
#   sh bench/two_rooms.sh [extra lvcl options]
set -e
out=${TMPDIR:-/tmp}/two_rooms.$$
mkdir -p "$out"
for case in 0.02:25 0.005:500 0.06:100 0.02:1; do
    t=${case%%:*} r=${case##*:}
    python3 scenes/make_two_rooms.py "$out/on.gltf" --thickness "$t" --ratio "$r" >/dev/null
    python3 scenes/make_two_rooms.py "$out/off.gltf" --thickness "$t" --ratio "$r" --bright-off >/dev/null
    for s in on off; do
        build/lvcl -q --mode lv --spp 16 --width 64 --particles 1e6 --seed 1 "$@" -o "$out/$s.exr" "$out/$s.gltf"
        eval "m_$s=\$(build/lvcl-compare $out/$s.exr $out/$s.exr | sed 's/.*\"mean\": \[\([0-9.e+-]*\),.*/\1/')"
    done
    printf '{"bench": "two_rooms", "wall_m": %s, "ratio": %s, "options": "%s", "mean_on": %s, "mean_off": %s, "on_over_off": %s}\n' \
        "$t" "$r" "$*" "$m_on" "$m_off" "$(python3 -c "print('%.4f' % ($m_on / $m_off))")"
done
rm -rf "$out"
