// TetGen .node, .ele and .face files (lib/tetmesh). The first byte picks
// the file the fuzzer writes; the other two are a small valid mesh (one
// tetrahedron and one of its faces), so each file's reader is reached.
#include "fuzz_input_file.hpp"
#include "stvd/tetmesh/tet_mesh.hpp"

namespace {
const char* const kNode = "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
const char* const kEle = "1 4 0\n1 1 2 3 4\n";
const char* const kFace = "1 0\n1 1 2 3\n";
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const int fuzzed = data[0] % 3;  // 0 .node, 1 .ele, 2 .face
  const std::string rest(reinterpret_cast<const char*>(data + 1), size - 1);
  const stvd::fuzz::FuzzInputFile node("mesh.node", fuzzed == 0 ? rest : kNode);
  const stvd::fuzz::FuzzInputFile ele("mesh.ele", fuzzed == 1 ? rest : kEle);
  const stvd::fuzz::FuzzInputFile face("mesh.face", fuzzed == 2 ? rest : kFace);
  try {
    stvd::tetmesh::readTetGenMesh(node.path());
  } catch (const stvd::tetmesh::TetMeshError&) {
  }
  return 0;
}
