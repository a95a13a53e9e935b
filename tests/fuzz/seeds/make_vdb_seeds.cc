// Writes the OpenVDB-made seeds of the `vdb` fuzz target (tests/fuzz/seeds/vdb/): small grids of
// every standard type, in every compression (Blosc, zlib, mask only, none), half floats, an
// instance, a frustum transform and the stream format, i.e. the layouts checkVdbStream walks.
// Not part of the build; to regenerate, from an empty directory:
//   g++ -std=c++17 make_vdb_seeds.cc -o make_vdb_seeds -lopenvdb -ltbb -lImath-3_1 &&
//   ./make_vdb_seeds
// The other .vdb seeds were written by the d2vdb command: `primitive sphere --center 3,3,3
// --radius 1 --voxel-size 0.25`, `primitive box ... --half`, and `field` on them and on small
// curve, polyline and point targets.
#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <fstream>
int main() {
  openvdb::initialize();
  auto ls = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(1.0f, openvdb::Vec3f(3.f),
                                                                     0.4f, 2.0f);
  ls->setName("surface");
  auto write = [](const std::string& name, openvdb::GridPtrVec grids, uint32_t compression) {
    openvdb::io::File f(name);
    f.setCompression(compression);
    f.write(grids);
    f.close();
  };
  using namespace openvdb::io;
  write("ls_zip.vdb", {ls}, COMPRESS_ZIP | COMPRESS_ACTIVE_MASK);
  write("ls_maskonly.vdb", {ls}, COMPRESS_ACTIVE_MASK);
  auto v = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.f));
  v->setName("vectors");
  v->tree().topologyUnion(ls->tree());
  for (auto it = v->beginValueOn(); it; ++it)
    it.setValue(openvdb::Vec3s(it.getCoord().x(), 1.f, 2.f));
  v->setTransform(ls->transform().copy());
  auto i = openvdb::Int32Grid::create(-1);
  i->setName("labels");
  i->tree().setValue(openvdb::Coord(1, 2, 3), 42);
  i->tree().addTile(2, openvdb::Coord(0, 0, 0), 7, true);
  auto d = openvdb::DoubleGrid::create(0.5);
  d->setName("d");
  d->tree().setValue(openvdb::Coord(9, 4, 100), 1.25);
  auto b = openvdb::BoolGrid::create(false);
  b->setName("b");
  b->tree().setValue(openvdb::Coord(5, 5, 5), true);
  b->tree().setValueOff(openvdb::Coord(6, 5, 5), true);
  auto m = openvdb::MaskGrid::create();
  m->setName("m");
  m->tree().setValueOn(openvdb::Coord(3, 0, 9));
  auto vd = openvdb::Vec3DGrid::create();
  vd->setName("vd");
  vd->tree().setValue(openvdb::Coord(0, 0, 0), openvdb::Vec3d(1, 2, 3));
  auto vi = openvdb::Vec3IGrid::create();
  vi->setName("vi");
  vi->tree().setValue(openvdb::Coord(0, 0, 0), openvdb::Vec3i(1, 2, 3));
  auto l = openvdb::Int64Grid::create();
  l->setName("l");
  l->tree().setValue(openvdb::Coord(0, 0, 0), 5);
  write("int32_blosc.vdb", {i}, COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK);
  write("double_zip.vdb", {d}, COMPRESS_ZIP | COMPRESS_ACTIVE_MASK);
  write("bool_blosc.vdb", {b}, COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK);
  write("bool_none.vdb", {b}, COMPRESS_NONE);
  write("mask_blosc.vdb", {m}, COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK);
  write("vec3d_zip.vdb", {vd}, COMPRESS_ZIP | COMPRESS_ACTIVE_MASK);
  write("vec3i_blosc.vdb", {vi}, COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK);
  write("int64_zip.vdb", {l}, COMPRESS_ZIP);
  v->setSaveFloatAsHalf(true);
  write("vectors_half.vdb", {v}, COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK);
  // An instance: two grids sharing one tree.
  auto shared = ls->copyGrid();
  shared->setName("copy");
  write("instance.vdb", {ls, shared}, COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK);
  // A frustum transform.
  auto fr = openvdb::FloatGrid::create(0.f);
  fr->setName("frustum");
  fr->setTransform(openvdb::math::Transform::createFrustumTransform(
      openvdb::BBoxd(openvdb::Vec3d(0), openvdb::Vec3d(10)), 0.5, 2.0, 0.1));
  fr->tree().setValue(openvdb::Coord(1, 1, 1), 3.f);
  write("frustum.vdb", {fr}, COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK);
  // Stream format (no grid offsets).
  {
    std::ofstream os("stream.vdb", std::ios::binary);
    openvdb::io::Stream(os).write(openvdb::GridPtrVec{ls});
  }
}
