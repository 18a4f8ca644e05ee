# SPDX-License-Identifier: MIT
# row.awk: one LAMMPS log of bench/lammps/pile.in as a row of bench_sim's CSV columns (used by
# bench/run_sim_bench.sh and bench/run_scaling.sh): best and median Loop time of the timed runs
# (the first run is the warm-up), the CPU-time figure from the "% CPU use" line (per rank),
# neighbour builds, memory per atom from "Per MPI rank memory allocation" (LAMMPS Mbytes = 2^20 B,
# per rank).
#   awk -v machine=M -v law=L -v steps=S -v repeats=K -v dt=DT -f bench/lammps/row.awk LOG
/^BENCH model/ { mobile = $5; fixed = $7 }
/^Loop time of/ { n++; t[n] = $4 }
/% CPU use with/ { c[n] = $1 + 0 }
/^Neighbor list builds/ { b[n] = $5 }
/^Per MPI rank memory allocation/ { mem = $(NF - 1) }
$1 ~ /^[0-9]+$/ && NF == 4 { cpg = $3 }
END {
    if (n < 2) exit 1
    best = -1; bestcpu = -1; builds = 0; k = 0
    for (i = 2; i <= n; i++) {
        s[++k] = t[i]; builds += b[i]
        if (best < 0 || t[i] < best) best = t[i]
        cpu = t[i] * c[i] / 100.0
        if (bestcpu < 0 || cpu < bestcpu) bestcpu = cpu
    }
    for (i = 1; i <= k; i++) for (j = i + 1; j <= k; j++) if (s[j] < s[i]) { x = s[i]; s[i] = s[j]; s[j] = x }
    median = s[int(k / 2) + 1]
    work = mobile * steps
    printf "%s,lammps,%s,%d,%d,%d,%d,%.6f,%.6f,%.3f,%.3f,%.3f,%.4f,,,%.3f,,,,%.1f,%s\n",
        machine, law, mobile, fixed, steps, k, best, median, work / best / 1e6,
        work / median / 1e6, work / bestcpu / 1e6, cpg, 1000.0 * builds / (steps * k),
        mem * 1048576.0 / (mobile + fixed), dt
}
