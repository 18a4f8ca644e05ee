/* SPDX-License-Identifier: MIT */
/* isa.c: which compiled copy of the hot loops (sim/isa/ files) a new world uses. sim/CMakeLists.txt
 * compiles those files once per instruction set and says which copies exist:
 * SIM_ISA_BUILT_AVX2, SIM_ISA_BUILT_AVX512 (x86-64), SIM_ISA_BUILT_NATIVE (a -march=native
 * build, then the only copy). The choice is made once per world, at create, from the CPU's
 * features (__builtin_cpu_supports), an explicit sim_isa_set, or SABLIER_ISA (docs/dev/isa.md). */
#include "internal.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#define DECLARE_KERNELS(suffix)                                                                    \
    StageFn *sim_contact_pass_select##suffix(unsigned key);                                        \
    StageFn *sim_wall_pass_select##suffix(unsigned key);                                           \
    FusedFn *sim_fused_pass_select##suffix(unsigned key);                                          \
    StageFn *sim_integrator_select##suffix(SimIntegrator integrator, int rotation);                \
    void sim_integrator_finish##suffix(SimWorld *world);
#define KERNELS(suffix)                                                                            \
    {                                                                                              \
        sim_contact_pass_select##suffix, sim_wall_pass_select##suffix,                             \
            sim_fused_pass_select##suffix, sim_integrator_select##suffix,                          \
            sim_integrator_finish##suffix                                                          \
    }

#if defined(SIM_ISA_BUILT_NATIVE)
DECLARE_KERNELS(_native)
static const SimKernels kernels[SIM_ISA_COUNT] = {[SIM_ISA_NATIVE] = KERNELS(_native)};
#else
#if defined(__x86_64__)
DECLARE_KERNELS(_sse2)
#define BASELINE KERNELS(_sse2)
#else
DECLARE_KERNELS(_generic)
#define BASELINE KERNELS(_generic)
#endif
#if defined(SIM_ISA_BUILT_AVX2)
DECLARE_KERNELS(_avx2)
#endif
#if defined(SIM_ISA_BUILT_AVX512)
DECLARE_KERNELS(_avx512)
#endif
static const SimKernels kernels[SIM_ISA_COUNT] = {
    [SIM_ISA_BASELINE] = BASELINE,
#if defined(SIM_ISA_BUILT_AVX2)
    [SIM_ISA_AVX2] = KERNELS(_avx2),
#endif
#if defined(SIM_ISA_BUILT_AVX512)
    [SIM_ISA_AVX512] = KERNELS(_avx512),
#endif
};
#endif

/* What the CPU runs. The AVX-512 copy is compiled with F and VL (256-bit operations on 32
 * registers, masks in k registers); the operating system's support of the wider state is part
 * of what __builtin_cpu_supports reports. */
static int cpu_runs(SimIsa isa)
{
#if defined(__x86_64__)
    __builtin_cpu_init();
    switch (isa) {
    case SIM_ISA_AVX2:
        return __builtin_cpu_supports("avx2");
    case SIM_ISA_AVX512:
        return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
    default:
        return 1;
    }
#else
    (void)isa;
    return 1;
#endif
}

static const char *const names[SIM_ISA_COUNT] = {
#if defined(__x86_64__)
    [SIM_ISA_BASELINE] = "sse2",
#else
    [SIM_ISA_BASELINE] = "generic",
#endif
    [SIM_ISA_AVX2] = "avx2",
    [SIM_ISA_AVX512] = "avx512",
    [SIM_ISA_NATIVE] = "native"};

const char *sim_isa_name(SimIsa isa)
{
    return (int)isa >= 0 && isa < SIM_ISA_COUNT ? names[isa] : NULL;
}

int sim_isa_from_name(const char *name)
{
    for (int k = 0; name && k < SIM_ISA_COUNT; ++k)
        if (strcmp(name, names[k]) == 0)
            return k;
    return -1;
}

int sim_isa_supported(SimIsa isa)
{
    if ((int)isa < 0 || isa >= SIM_ISA_COUNT || !kernels[isa].contact_pass)
        return 0;
    return cpu_runs(isa);
}

/* -1 until the first sim_isa or sim_isa_set. Atomic: worlds may be created on several threads. */
static _Atomic int chosen = -1;

static SimIsa best(void)
{
    for (int k = SIM_ISA_COUNT - 1; k > 0; --k)
        if (sim_isa_supported((SimIsa)k))
            return (SimIsa)k;
    return SIM_ISA_BASELINE;
}

SimIsa sim_isa(void)
{
    int isa = atomic_load(&chosen);
    if (isa >= 0)
        return (SimIsa)isa;
    isa = sim_isa_from_name(getenv("SABLIER_ISA"));
    if (isa < 0 || !sim_isa_supported((SimIsa)isa))
        isa = (int)best();
    atomic_store(&chosen, isa);
    return (SimIsa)isa;
}

SimStatus sim_isa_set(SimIsa isa)
{
    if (!sim_isa_supported(isa))
        return SIM_ERROR_INVALID;
    atomic_store(&chosen, (int)isa);
    return SIM_OK;
}

const SimKernels *sim_kernels(void)
{
    return &kernels[sim_isa()];
}
