# Sourced by the method scripts (carryover-data.sh, method-tables.sh,
# rigid-train.sh): sets `vref` to the release binary, and stops the
# script with the command that builds it when it is not built.
# VREF_BIN names another binary (a copy, so that a rebuild mid-run does
# not change what is measured).
vref=${VREF_BIN:-target/release/vref}
[ -x "$vref" ] || {
  echo "$(basename "$0"): $vref is not built; run: cargo build --release -p vref -p vref-research --bins --examples" >&2
  exit 2
}
