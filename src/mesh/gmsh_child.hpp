#pragma once
// Gmsh in a child process: the model of a file, read (or meshed) by Gmsh's library
// in a process of its own (fork), within limits of time and memory. Whatever Gmsh
// does to a bad file stays in the child: Gmsh 4.8's .msh readers crash on some
// malformed files (fuzz/, docs/reliability.md), `Exit;` in a .geo script ends the
// process, and Gmsh keeps global state. gmsh_reader.cpp checks the model and builds the Mesh.
#include "mesh/gmsh_model.hpp"
#include "mesh/gmsh_reader.hpp"

#include <string>

namespace vpc {

/// Runs Gmsh on `file` in a child process and returns its model, or throws its
/// error (vpc::Error naming the file): Gmsh's own, a crash, `Exit;`, or a limit of
/// `options` reached.
gmsh_model::GmshModel read_in_child(const std::string& file, const GmshOptions& options);

}  // namespace vpc
