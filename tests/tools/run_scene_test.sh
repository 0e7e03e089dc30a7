#!/bin/sh
# scripts/run_scene.sh runs the scene: exit 0, its results files with rows
# and its plot. Co-simulated and host-only scenes for 10 ms of simulated
# time without their report (too short for blows); FE-only scenes to their
# deck's end.
#   run_scene_test.sh RUN_SCENE.sh SCENE     one scene
#   run_scene_test.sh RUN_SCENE.sh --all-listed SCENES_DIR
#                                            every scene folder has its row
run=$1 scene=$2
if [ "$scene" = --all-listed ]; then
  listed=$(bash "$run" --list | cut -d' ' -f1 | sort)
  folders=$(for d in "$3"/*/; do basename "$d"; done | sort)
  [ "$listed" = "$folders" ] && { echo "ok   every scene folder is listed: $(echo $folders)"; exit 0; }
  echo "FAIL: scene folders and run_scene.sh's table differ:"; diff -u "$(printf '%s\n' "$folders" > /tmp/f.$$; echo /tmp/f.$$)" \
    "$(printf '%s\n' "$listed" > /tmp/l.$$; echo /tmp/l.$$)"; rm -f /tmp/f.$$ /tmp/l.$$; exit 1
fi
out=$(mktemp -d "${TMPDIR:-/tmp}/pcs_scene_XXXXXX")
trap 'rm -rf "$out"' EXIT
kind=$(bash "$run" --list | awk -v s="$scene" '$1 == s {print $2}')
[ -n "$kind" ] || { echo "FAIL: run_scene.sh does not list $scene"; exit 1; }
if [ "$kind" = fe ]; then
  bash "$run" "$scene" --out "$out" > "$out/log" 2>&1; rc=$?
else
  bash "$run" "$scene" --out "$out" --quiet --no-report --set simulation.stoptime=0.01 > "$out/log" 2>&1; rc=$?
fi
[ $rc -eq 0 ] || { echo "FAIL: run_scene.sh $scene exited $rc"; cat "$out/log"; exit 1; }
for f in "$scene.png" $( [ "$kind" != host ] && echo fe_results.h5 ) $( [ "$kind" != fe ] && echo host_results.h5 ); do
  [ -s "$out/$f" ] || { echo "FAIL: $scene wrote no $f"; cat "$out/log"; exit 1; }
done
echo "ok   run_scene.sh $scene ($kind): $(ls "$out" | tr '\n' ' ')"
