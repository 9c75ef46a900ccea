// Bounds on every size and count that enters from outside (files, scene fields, generator parameters, the
// command line). Input beyond a bound is rejected where it enters, with a message naming the field and the bound,
// before anything is allocated for it, so no input can overflow an int index or exhaust the memory.
//
// Why these values:
// - vertices, faces: 3N unknowns and the Hessian's ~170 N non-zeros must fit the int indices of the sparse
//   matrices with room to spare (4e6 vertices → ~7e8 non-zeros); such a mesh already needs tens of GB to solve.
// - steps: time steps (duration / timeStep) and relaxation steps; 1e7 steps of 60 Hz dynamics are 46 hours of
//   simulated time.
// - load levels: a static analysis' loadSteps, levels 1/N apart; the statics path takes no load increment below
//   1e-4 (LoadSteppingOptions::minIncrement, solvers/statics.h), so 10,000 levels is the finest it can follow
//   (a finer one was refused inside the solver, with a message that named its option, not the scene's field).
// - Newton iterations per step, threads: far above any useful value, far below what breaks OpenMP or an int.
// - file sizes, line length, JSON depth and string length: bound the memory a hostile file can claim (an OBJ
//   line, a JSON document) and the recursion of everything that walks a JSON tree.
//
// The values are a mutable process-wide struct so that a harness (the fuzzers) can lower them to keep each input
// cheap; the program never changes them.
#pragma once

#include <cstdint>

namespace jetshell {

struct InputLimits {
  std::int64_t maxVertices = 4'000'000;      // per mesh and per scene (all shell actors stacked)
  std::int64_t maxFaces = 8'000'000;         // per mesh and per scene
  std::int64_t maxSteps = 10'000'000;        // time steps, relaxation steps
  std::int64_t maxLoadLevels = 10'000;       // static loadSteps: 1 / LoadSteppingOptions::minIncrement
  std::int64_t maxEndMoments = 64;           // moment loads per scene (each one an energy term of its own)
  std::int64_t maxConditions = 10'000;       // fixed conditions, loads and probes, each per scene
  std::int64_t maxSelectedVertices = 16'000'000;  // vertices selected by all fixed conditions and loads together
  // Actors: each costs its own size (its mesh, its terms) and a few KB besides. Each pair of a shell actor and
  // a volume actor has contact terms of its own (about 4 KB: 1,000 × 1,000 pairs took 4.1 GB), and each volume
  // actor samples every shell vertex (80-110 bytes per volume actor and vertex).
  std::int64_t maxActors = 100'000;              // shell and volume actors together
  std::int64_t maxContactPairs = 100'000;        // shell actors × volume actors
  std::int64_t maxVolumeActorVertices = 50'000'000;  // volume actors × the shell vertices
  std::int64_t maxKeyframes = 1'000'000;     // keyframes of all volume actors of a scene together (56 bytes each)
  std::int64_t maxIterations = 1'000'000;    // Newton iterations per step
  int maxThreads = 256;                      // solver.threads
  std::int64_t maxObjBytes = 1LL << 30;      // OBJ file size (1 GiB)
  std::int64_t maxObjLineBytes = 1 << 16;    // one OBJ line (64 KiB)
  std::int64_t maxSdfBytes = 1LL << 30;      // SDF grid file size (1 GiB: 16.7M samples at up to 60 bytes each)
  // Samples of all SDF grid files of a scene together, each file counted once however many sdfGrid actors name
  // it: the scene reader reads each file once, and a run holds each file's grid once (8 bytes a sample). Four
  // grids of the largest size one file may have (16,777,216 samples).
  std::int64_t maxSdfSamples = 4LL << 24;
  std::int64_t maxSdfLineBytes = 64LL << 20;  // one SDF grid line (64 MiB: a 256 x 256 slice per line fits)
  std::int64_t maxJsonBytes = 256LL << 20;   // scene (JSON) file size (256 MiB)
  int maxJsonDepth = 64;                     // nesting of JSON arrays and objects
  std::int64_t maxStringBytes = 4096;        // any JSON string (names, paths, description)
  // Physical magnitudes whose squares and reciprocals the solvers form: past them energies overflow to inf.
  double maxDistance = 1e6;                  // m (and m/s): prescribed displacements and velocities, translations
  double maxAcceleration = 1e6;              // m/s²: gravity (a fall of at most maxDistance in its first second)
  double maxAngularVelocity = 1e6;           // rad/s: a volume actor's constant turn
  double minTimeStep = 1e-9;                 // s: time steps of dynamics and relaxation (1/Δt² stays finite)
  double maxDampingCoefficient = 1e9;        // 1/s (mass damping α_R) and s (stiffness damping β_R)
};

/// The limits in force (defaults above).
inline InputLimits& inputLimits() {
  static InputLimits limits;
  return limits;
}

}  // namespace jetshell
