#!/usr/bin/env bash
# The Python module's tests, against the module as a user installs it:
# build the abi3 wheel with maturin (sharing the crate's release build under
# target/), install it into a fresh virtual environment with no Rust
# toolchain on PATH, and run pytest from outside the source tree.
set -euo pipefail
cd "$(dirname "$0")/.."
root="$PWD"
export CARGO_TARGET_DIR="$root/target"
quiet=(--quiet --disable-pip-version-check)

# the build tool, in an environment of its own
python3 -m venv target/python-build
target/python-build/bin/pip install "${quiet[@]}" 'maturin>=1.7,<2'
rm -f target/wheels/granular_automata-*.whl
(cd python && "$root/target/python-build/bin/maturin" build --release --locked --quiet)
wheels=(target/wheels/granular_automata-*-abi3-*.whl)
[ -f "${wheels[0]}" ] || { echo "python/test.sh: no abi3 wheel in target/wheels" >&2; exit 1; }
wheel="$root/${wheels[0]}"
echo "wheel: ${wheel#"$root"/} ($(du -k "$wheel" | cut -f1) KiB)"

# PATH without any folder that holds cargo or rustc
path=""
IFS=: read -ra dirs <<<"$PATH"
for d in "${dirs[@]}"; do
    [ -e "$d/cargo" ] || [ -e "$d/rustc" ] || path="${path:+$path:}$d"
done

# a fresh environment, the wheel installed without a Rust toolchain
venv="$root/target/python-venv"
rm -rf "$venv"
python3 -m venv "$venv"
run() { env PATH="$venv/bin:$path" VIRTUAL_ENV="$venv" "$@"; }
if run sh -c 'command -v cargo || command -v rustc'; then
    echo "python/test.sh: cargo or rustc is still on PATH" >&2
    exit 1
fi
run pip install "${quiet[@]}" --only-binary granular-automata "$wheel" numpy pytest

# from a folder outside the source tree, so only the installed module can
# be imported
work="$root/target/python-test"
rm -rf "$work"
mkdir -p "$work"
cd "$work"
run python - "$venv" <<'EOF'
import pathlib, sys
import granular_automata as ga
where = pathlib.Path(ga.__file__).resolve()
assert pathlib.Path(sys.argv[1]).resolve() in where.parents, f"imported {where}"
print(f"granular_automata {ga.__version__} from {where.parent}")
EOF
run python -m pytest -q -p no:cacheprovider "$root/python/tests"
