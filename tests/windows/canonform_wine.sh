#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# `canonform` for the end-to-end scripts of tests/e2e/: the Windows build's canonform.exe
# ($CANONFORM_EXE) under Wine (tools/wine.sh), with its arguments and exit status.
exec "$(dirname "$(realpath "$0")")/../../tools/wine.sh" "${CANONFORM_EXE:?CANONFORM_EXE names canonform.exe}" "$@"
