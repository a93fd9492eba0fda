#!/usr/bin/env bash
# Feeds the real s3m binary bad inputs and prints what the user sees, as the markdown table rows of
# docs/ROBUSTNESS.md (case | command | exit | message). Every case must fail cleanly: exit 1
# ("s3m: error: ...") or a command-line usage error (CLI11, exit 100..127); never succeed, crash
# (exit >= 128) or report an unexpected error (exit 2). The script exits 1 otherwise.
# Usage: tools/robustness.sh [path/to/s3m]   (default build/src/apps/s3m)
set -uo pipefail
cd "$(dirname "$0")/.."
S3M="$(realpath "${1:-build/src/apps/s3m}")"
[ -x "$S3M" ] || { echo "robustness.sh: no s3m binary at $S3M (build it first)" >&2; exit 2; }
W="$(mktemp -d /tmp/s3m_robust_XXXXXX)"
trap 'rm -rf "$W"' EXIT
cd "$W"
bad=0

# row "case" cmd args... : runs the command in $W, prints one table row with its first stderr line.
row() {
  local name="$1"; shift
  local err code
  "$@" >/dev/null 2>stderr.txt
  code=$?
  err="$(grep -v '^\s*$' stderr.txt | head -n 3 | tr '\n' ' ' | sed 's/ *$//; s/|/\\|/g')"
  local shown="${*/#$S3M/s3m}"
  printf '| %s | `%s` | %s | %s |\n' "$name" "$shown" "$code" "$err"
  if [ "$code" != 1 ] && { [ "$code" -lt 100 ] || [ "$code" -ge 128 ]; }; then bad=1; printf '| ^ NOT CLEAN | | | |\n'; fi
}

# ---- inputs --------------------------------------------------------------------------------
gt=gt.txt
{ echo "# t tx ty tz qx qy qz qw"; for i in $(seq 0 49); do printf '%d.%02d0000 %s 0 1 0 0 0 1\n' $((i / 10)) $((i % 10 * 10)) "0.0$i"; done; } > $gt
head -c 700 $gt > truncated.txt                        # cut in the middle of a line
# setcol FILE LINE COL VALUE: data line LINE (1-based, comments not counted) gets VALUE in column COL.
setcol() { awk -v l="$2" -v c="$3" -v v="$4" '/^#/ {print; next} {n++; if (n == l) $c = v; print}' "$1"; }
setcol $gt 5 2 nan > nan_pose.txt
setcol $gt 5 8 2 > bad_quat.txt
printf '# only comments\n\n' > empty.txt
awk '!/^#/ {printf "%.6f %s %s %s %s %s %s %s\n", $1 + 1000, $2, $3, $4, $5, $6, $7, $8}' $gt > shifted.txt
setcol $gt 6 1 0.300000 > unsorted.txt
head -c 300 /dev/urandom > garbage.txt
printf '1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0.1 0 1 0 0 0 0 1 0\n1 0 0 0.2 0 1 0 0 0 0 1 0\n' > kitti_gt.txt
printf '1 0 0 0 0 1 0 0 0 0 1 0\n1e308 1e308 0 0 1e308 -1e308 0 0 0 0 1 0\n' > kitti_bad.txt
setcol $gt 5 2 1e300 > huge.txt
mkdir -p outdir && cp $gt est.txt

echo "| case | command | exit | message |"
echo "|---|---|---|---|"
row "missing file" "$S3M" eval --gt missing.txt --est $gt
row "truncated trajectory (cut mid-line)" "$S3M" eval --gt $gt --est truncated.txt --no-plots
row "NaN in a pose" "$S3M" eval --gt $gt --est nan_pose.txt --no-plots
row "non-unit quaternion" "$S3M" eval --gt $gt --est bad_quat.txt --no-plots
row "empty trajectory (comments only)" "$S3M" eval --gt $gt --est empty.txt --no-plots
row "timestamps that match nothing in the ground truth" "$S3M" eval --gt $gt --est shifted.txt --no-plots
row "timestamps not increasing" "$S3M" eval --gt $gt --est unsorted.txt --no-plots
row "binary garbage as trajectory" "$S3M" eval --gt $gt --est garbage.txt --no-plots
row "KITTI matrix that is not a rotation (huge entries)" "$S3M" eval --gt kitti_gt.txt --est kitti_bad.txt --format kitti --no-plots
row "huge translation (1e300 m)" "$S3M" eval --gt $gt --est huge.txt --no-plots
# Out of disk while writing results: the file-size limit makes every write beyond 1 KiB fail
# (SIGXFSZ ignored, so the write returns EFBIG like a full disk returns ENOSPC).
"$S3M" eval --gt $gt --est est.txt --out outdir --no-plots >/dev/null 2>&1
before=$(md5sum outdir/metrics.json | cut -d' ' -f1)
sed -i '3,$s/ 1 0 0 0 1$/ 1.001 0 0 0 1/' est.txt
row "disk full while writing outputs (ulimit -f 1)" bash -c "trap '' XFSZ; ulimit -f 1; exec \"\$0\" \"\$@\"" "$S3M" eval --gt $gt --est est.txt --out outdir --no-plots
after=$(md5sum outdir/metrics.json | cut -d' ' -f1)
if [ "$before" = "$after" ] && /usr/bin/python3 -c "import json,sys; json.load(open('outdir/metrics.json'))"; then
  echo "<!-- disk-full case: previous outdir/metrics.json unchanged and still valid JSON -->"
else
  echo "<!-- disk-full case: previous metrics.json was changed or is unreadable -->"; bad=1
fi
exit $bad
