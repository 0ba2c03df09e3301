#!/usr/bin/env bash
# Renders one archwave frame as a Slurm job array and merges it (docs/production.md#slurm):
#
#   scripts/slurm/submit.sh SCENE.json OUT.exr --parts N --spp SPP [--split samples|tiles]
#       [--workdir DIR] [--checkpoint SECONDS] [--archwave PATH] [-- ARCHWAVE ARGS... [-- SBATCH ARGS...]]
#
# Submits an array of N tasks (render_part.sbatch: one sample range or band each, its log in
# DIR/logs/part_<job>_<task>.log) and a merge job that runs once all of them succeeded
# (merge.sbatch, --dependency=afterok, log DIR/logs/merge_<job>.log). Prints
# "ARRAY_JOB_ID MERGE_JOB_ID". DIR (default: OUT.exr's directory + /OUT.parts) must be on a
# file system every node sees; so must the scene and the archwave binary.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
usage() { sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
[ $# -ge 2 ] || usage
scene="$(realpath "$1")"; out="$(realpath -m "$2")"; shift 2
parts="" spp="" split=samples workdir="" checkpoint=300
archwave="$(realpath -m "$here/../../build/archwave")"
extra=() sbatch_extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --parts) parts="$2"; shift 2 ;;
    --spp) spp="$2"; shift 2 ;;
    --split) split="$2"; shift 2 ;;
    --workdir) workdir="$(realpath -m "$2")"; shift 2 ;;
    --checkpoint) checkpoint="$2"; shift 2 ;;
    --archwave) archwave="$(realpath -m "$2")"; shift 2 ;;
    --) shift
        while [ $# -gt 0 ] && [ "$1" != "--" ]; do extra+=("$1"); shift; done
        if [ $# -gt 0 ]; then shift; sbatch_extra=("$@"); fi
        break ;;
    *) echo "submit.sh: unknown argument '$1'" >&2; usage ;;
  esac
done
[[ "$parts" =~ ^[1-9][0-9]*$ ]] || { echo "submit.sh: --parts N (N >= 1) is required" >&2; exit 2; }
[[ "$spp" =~ ^[1-9][0-9]*$ ]] || { echo "submit.sh: --spp SPP (>= 1) is required: every part must agree on it" >&2; exit 2; }
[ "$split" = samples ] || [ "$split" = tiles ] || { echo "submit.sh: --split is samples or tiles" >&2; exit 2; }
[ -f "$scene" ] || { echo "submit.sh: no scene file $scene" >&2; exit 2; }
[ -x "$archwave" ] || { echo "submit.sh: no archwave binary at $archwave (build it, or --archwave PATH)" >&2; exit 2; }
[ -n "$workdir" ] || workdir="$(dirname "$out")/$(basename "$out" .exr).parts"
mkdir -p "$workdir/logs"
printf '%s\n' "${extra[@]+"${extra[@]}"}" > "$workdir/archwave_args.txt"
export AW_ARCHWAVE="$archwave" AW_SCENE="$scene" AW_OUTDIR="$workdir" AW_PARTS="$parts" AW_SPP="$spp"
export AW_SPLIT="$split" AW_CHECKPOINT="$checkpoint" AW_OUTPUT="$out" AW_EXTRA_FILE="$workdir/archwave_args.txt"
array=$(sbatch --parsable --export=ALL --array="0-$((parts - 1))" --output="$workdir/logs/part_%A_%a.log" \
        "${sbatch_extra[@]+"${sbatch_extra[@]}"}" "$here/render_part.sbatch")
array="${array%%;*}"
merge=$(sbatch --parsable --export=ALL --dependency="afterok:$array" --kill-on-invalid-dep=yes \
        --output="$workdir/logs/merge_%j.log" "${sbatch_extra[@]+"${sbatch_extra[@]}"}" "$here/merge.sbatch")
merge="${merge%%;*}"
echo "$array $merge"
