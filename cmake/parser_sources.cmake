# The input boundary: everything that reads, checks and resolves an OBJ mesh, a scene file, a fit file (with its
# target shapes and CSV curves) or an output frame (.vtu, .pvd), and nothing that solves. The main build makes it
# the library jetshell_parsers, which jetshell_lib links, so a parser that starts to need solver code fails to
# link in the main build (the corpus replay tests link jetshell_parsers alone); the fuzz build (tests/fuzz)
# compiles the same list with libFuzzer and the sanitizers.
set(JETSHELL_PARSER_SOURCES
  core/input_file.cpp core/mesh_io.cpp core/topology.cpp core/mesh_generators.cpp core/garment_generator.cpp
  energies/shell/material.cpp energies/contact/sdf_grid.cpp energies/contact/volume_shapes.cpp
  energies/contact/rigid_path.cpp
  tools/scene/json_reader.cpp tools/scene/scene_json.cpp tools/scene/scene.cpp tools/scene/scene_model.cpp
  tools/scene/contact_coverage.cpp tools/scene/contact_at_start.cpp tools/scene/inside_solids.cpp tools/scene/sliver_faces.cpp tools/scene/near_pairs.cpp tools/scene/open_seams.cpp tools/scene/volume_shape.cpp
  tools/scene/actor_params.cpp tools/scene/generated_shapes.cpp tools/scene/shapes.cpp tools/scene/selector.cpp
  tools/output/vtu_reader.cpp tools/output/run_checkpoint.cpp tools/fit/fit_file.cpp tools/fit/fit_options.cpp tools/fit/material_base.cpp)
list(TRANSFORM JETSHELL_PARSER_SOURCES PREPEND "${PROJECT_SOURCE_DIR}/")
