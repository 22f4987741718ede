#!/usr/bin/env bash
# Creates (or checks) the project's Python venv at the workspace root, with the pinned versions of
# python `canopen` and `python-can`, and of the other buses' peers (EtherNet/IP `cpppo` and
# `ethernetip`, PROFINET `pnio-dcp` and `profinet-py`, PROFIBUS `pyprofibus`, EtherCAT `pysoem`),
# that the differential and interoperability tests compare against. Idempotent: installs only
# what is missing or at another version. Prints the python path.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
venv="$root/.venv"
python="$venv/bin/python"

if [ ! -x "$python" ]; then
    python3 -m venv "$venv" >&2
fi

wanted=("canopen==2.4.1" "python-can==4.6.1" "cpppo==5.2.5" "ethernetip==1.2.0" "pnio-dcp==1.2.0"
        "profinet-py==0.6.6" "pyprofibus==1.13" "pyserial==3.5" "pysoem==1.1.13")
missing=()
for requirement in "${wanted[@]}"; do
    name="${requirement%%==*}"
    version="${requirement##*==}"
    installed="$("$python" -m pip show "$name" 2>/dev/null | sed -n 's/^Version: //p' || true)"
    if [ "$installed" != "$version" ]; then
        missing+=("$requirement")
    fi
done
if [ "${#missing[@]}" -gt 0 ]; then
    "$python" -m pip install --quiet --disable-pip-version-check "${missing[@]}" >&2
fi
echo "$python"
