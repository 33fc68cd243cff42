#!/usr/bin/env bash
# One line describing where and when a benchmark ran: CPU, cores, date, commit.
cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')
commit=$(git -C "$(dirname "$0")/../.." rev-parse --short HEAD 2>/dev/null || echo unknown)
# The bench's own outputs (docs/) do not make the code dirty.
dirty=$(git -C "$(dirname "$0")/../.." status --porcelain -- . ':!docs' 2>/dev/null | grep -q . && echo "+changes" || true)
echo "Machine: ${cpu:-unknown CPU}, $(nproc) cores, $(free -g | awk '/Mem:/{print $2}') GiB; date $(date -u +%Y-%m-%d); commit ${commit}${dirty}."
