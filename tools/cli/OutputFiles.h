// The output files of a sub-command, declared once per command and checked together before it
// runs: every name's directory must exist and be writable and its extension must name what is
// written there (d2vdb/core/OutputPath.h), so that no command works for minutes and then fails
// on its output, or writes one kind of file under another kind's name.
#pragma once

#include <string>
#include <vector>

namespace d2vdb::cli {

/// What a command writes to a file; each decides the extensions the file's name may have.
enum class OutputFormat {
  Vdb,        ///< .vdb (level sets, fields)
  Mesh,       ///< .obj, .ply, .stl
  MeshOrVdb,  ///< a mesh, or a level set in a .vdb (offset)
  ObjOrPly,   ///< a mesh with per-vertex attributes: .obj, .ply
  Ply,        ///< a PLY mesh (per-vertex properties)
  Json,       ///< .json
  Svg,        ///< .svg
  Table,      ///< per-point answers: .csv, .json, .ply
};

/// One output file of a command.
struct OutputFile {
  std::string option;       ///< the option that names it, as the user typed it: "output", "--mesh"
  std::string path;         ///< empty: not requested (nothing is checked)
  OutputFormat format;      ///< what is written there
  std::string reason = {};  ///< why the format is restricted, for the message (optional)
};

/// Throws InputError (exit code 2) naming the option when an output cannot be written under its
/// name (checkOutputPath()) or two outputs name the same file; called by the command registry
/// with the list of the chosen command before its run function.
void checkOutputFiles(const std::vector<OutputFile>& outputs);

}  // namespace d2vdb::cli
