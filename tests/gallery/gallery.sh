#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The ctest `gallery` (docs/gallery.md): remakes the thesis figures at reduced size and compares
# them with tests/gallery/reference/ through `sablier diff` on the two folders.
#   tests/gallery/gallery.sh SABLIER WORK
set -euo pipefail
sablier=${1:?usage: gallery.sh SABLIER WORK}
work=${2:?usage: gallery.sh SABLIER WORK}
root=$(cd "$(dirname "$0")/../.." && pwd)
rm -rf "$work"
"$root/scripts/gallery.sh" --reduced --sablier "$sablier" "$work/fresh"
status=0
"$sablier" diff "$root/tests/gallery/reference" "$work/fresh" --report "$work/report" || status=$?
if [ $status -ne 0 ]; then
  cat >&2 <<MSG
gallery: the figures differ from tests/gallery/reference/ (exit $status): see
  $work/report/index.html
If the change is intended (a new look of the figures, a physics change), regenerate the
references and commit them:
  make gallery-update        (= scripts/gallery.sh --reduced OUT, then
                              sablier diff tests/gallery/reference OUT --update)
MSG
fi
exit $status
