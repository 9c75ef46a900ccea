// JETSHELL_FLATTEN: inline every call in a function's body, recursively, into that function.
//
// Ceres' Jet arithmetic is a chain of small inline functions (each operator builds an Eigen expression for the
// dual part, and Eigen assigns it in a loop function of its own). In a translation unit that instantiates many
// templates, g++ runs out of its unit-wide inlining budget and leaves these as calls: in the bending term's
// stages a profile showed Eigen's 3-vector assignment loop, called once per Jet operation, as the single
// hottest function of the AD path. The framework's stage evaluators (core/stage.h, core/stage_derivatives.h)
// are small, so flattening them costs little code and makes a user's stage function, and every Jet operation
// in it, one straight-line body — without touching the user's code or the unit's optimisation flags.
#pragma once

// The sanitizer build (JETSHELL_SANITIZE) defines JETSHELL_NO_FLATTEN: flattened bodies under AddressSanitizer
// took its CI pass from 509 to 955 s, and the checks it runs do not depend on what is inlined.
#if (defined(__GNUC__) || defined(__clang__)) && !defined(JETSHELL_NO_FLATTEN)
#define JETSHELL_FLATTEN __attribute__((flatten))
#else
#define JETSHELL_FLATTEN
#endif

// JETSHELL_FLATTEN_SWEEP: the stage graph's per-element sweeps (core/stage_graph_evaluator.h), flattened only when
// the build asks for it (CMake option JETSHELL_FLATTEN_SWEEPS, off by default). Flattened, a sweep becomes one
// body holding every stage's Jets and every curvature block of the graph: the staged membrane and bending terms
// run 5–10% faster (BENCHMARKS.md, Elements, "Session 23"), but energies/shell/bending_term_staged.cpp takes
// about 245 s and 2.2 GB to compile instead of 26 s and 1.1 GB.
#if defined(JETSHELL_FLATTEN_SWEEPS)
#define JETSHELL_FLATTEN_SWEEP JETSHELL_FLATTEN
#else
#define JETSHELL_FLATTEN_SWEEP
#endif
// JETSHELL_INLINE: a helper of the stage graph's sweeps (a 3×3 block add, a node's slots, a node's curvature)
// inlined into each sweep that calls it. Left to the unit-wide inlining budget, g++ kept several of them as calls
// (one per block or per node); inlined, the staged shell's exact Hessian costs about 5% less at 80,000 faces, at no
// cost in compile time (BENCHMARKS.md, Elements, "Session 77"). The sanitizer build leaves them to the compiler.
#if (defined(__GNUC__) || defined(__clang__)) && !defined(JETSHELL_NO_FLATTEN)
#define JETSHELL_INLINE __attribute__((always_inline)) inline
#else
#define JETSHELL_INLINE inline
#endif
// JETSHELL_LAMBDA_INLINE: the same for a lambda's body, written after its parameter list: a sweep's per-node and
// per-element lambdas (core/stage_graph_evaluator.h, inWindows) inlined into the loops that call them.
#if (defined(__GNUC__) || defined(__clang__)) && !defined(JETSHELL_NO_FLATTEN)
#define JETSHELL_LAMBDA_INLINE __attribute__((always_inline))
#else
#define JETSHELL_LAMBDA_INLINE
#endif
