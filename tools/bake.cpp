// bake: photon-traced irradiance on every vertex of an OBJ or glTF scene, written as a PLY that MeshLab opens.
// Exit status: 0 on success, 1 for bad input (message names file:line), 2 for a bad command line.
#include "tools/bake_cli.h"

int main(int argc, char** argv) { return pb::tools::RunBake(argc, argv); }
