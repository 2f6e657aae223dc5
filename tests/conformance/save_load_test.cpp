// Conformance after save and load through the Accelerator interface: every structure with supports_save() saved,
// loaded back (into a fresh instance of its spec, and by load_accelerator(), which reads the kind from the file) and
// giving bit-identical answers; truncated, foreign, wrong-version, corrupted and stale (the scene moved since) files
// refused with an Error naming the file and the fault. Structures without saving say so, naming themselves.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../file_bytes.h"
#include "oracle.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/core/error.h"
#include "test_scenes.h"

namespace rayaccel::conformance {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> specs_where(bool (Accelerator::*supports)() const, bool wanted) {
  std::vector<std::string> out;
  for (const std::string& spec : variant_specs()) {
    if ((*make_accelerator(spec).*supports)() == wanted) out.push_back(spec);
  }
  return out;
}

using testing::expect_error;
using testing::read_all;
using testing::write_all;

class SaveLoad : public ConformanceTest {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("rayaccel_save_load_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

void expect_identical_answers(const Accelerator& a, const Accelerator& b, const std::vector<Ray>& rays,
                              const std::string& label) {
  int faults = 0;
  for (const Ray& ray : rays) {
    const Hit x = a.intersect(ray), y = b.intersect(ray);
    if (x.prim_id != y.prim_id || !(x.t == y.t || (std::isinf(x.t) && std::isinf(y.t))) || x.u != y.u ||
        x.v != y.v || a.occluded(ray) != b.occluded(ray)) {
      if (++faults <= 3) ADD_FAILURE() << label << ": " << describe(ray) << ": " << describe(x) << " vs " << describe(y);
    }
  }
  EXPECT_EQ(faults, 0) << label;
}

TEST_P(SaveLoad, RoundTripGivesIdenticalAnswers) {
  const SceneCase& c = small_scene_cases().front();
  auto built = build_checked(GetParam(), c.scene);
  const fs::path file = dir_ / "saved.bin";
  built->save(file);
  auto loaded = make_accelerator(GetParam());
  loaded->load(file, c.scene);
  EXPECT_TRUE(loaded->validate().empty());
  expect_identical_answers(*built, *loaded, c.rays, "load");
  const auto found = load_accelerator(file, c.scene);
  EXPECT_TRUE(found->validate().empty());
  expect_identical_answers(*built, *found, c.rays, "load_accelerator (" + found->spec() + ")");
  expect_matches_brute_force(*found, c.scene, c.rays, "loaded");
}

TEST_P(SaveLoad, BadFilesGiveErrorsNamingTheFile) {
  TriangleMesh mesh = closed_sphere_mesh(8, 10);
  Scene scene = Scene::from_mesh(mesh, "sphere");
  auto built = build_checked(GetParam(), scene);
  const fs::path good = dir_ / "good.bin";
  built->save(good);
  const std::vector<char> bytes = read_all(good);
  auto target = make_accelerator(GetParam());

  const fs::path missing = dir_ / "missing.bin";
  expect_error([&] { target->load(missing, scene); }, missing.string(), "cannot be opened");
  expect_error([&] { load_accelerator(missing, scene); }, missing.string(), "cannot be opened");

  const fs::path truncated = dir_ / "truncated.bin";
  write_all(truncated, std::vector<char>(bytes.begin(), bytes.begin() + static_cast<long>(bytes.size() / 2)));
  expect_error([&] { target->load(truncated, scene); }, truncated.string(), "truncated");
  expect_error([&] { load_accelerator(truncated, scene); }, truncated.string(), "truncated");
  write_all(truncated, std::vector<char>(bytes.begin(), bytes.begin() + 12));
  expect_error([&] { target->load(truncated, scene); }, truncated.string(), "truncated");

  const fs::path foreign = dir_ / "foreign.bin";
  write_all(foreign, std::vector<char>(300, 'x'));
  expect_error([&] { target->load(foreign, scene); }, foreign.string(), "not a rayaccel");
  expect_error([&] { load_accelerator(foreign, scene); }, foreign.string(), "not a saved rayaccel structure");

  const fs::path version = dir_ / "version.bin";
  std::vector<char> patched = bytes;
  const std::uint32_t future = 99;  // both formats: the version follows the 8-byte magic
  std::memcpy(patched.data() + 8, &future, sizeof future);
  write_all(version, patched);
  expect_error([&] { target->load(version, scene); }, version.string(), "version 99 is not supported");
  expect_error([&] { load_accelerator(version, scene); }, version.string(), "version 99 is not supported");

  const fs::path corrupted = dir_ / "corrupted.bin";
  patched = bytes;
  patched[patched.size() - 20] ^= 0x40;
  write_all(corrupted, patched);
  expect_error([&] { target->load(corrupted, scene); }, corrupted.string(), "checksum mismatch");

  // Stale: the scene moved after the save.
  for (Vec3& v : mesh.vertices) v = Vec3{v.x * 1.5f, v.y, v.z};
  scene.set_vertices(mesh.vertices);
  expect_error([&] { target->load(good, scene); }, good.string(), "another scene");
  expect_error([&] { load_accelerator(good, scene); }, good.string(), "another scene");
  const Scene other = Scene::from_mesh(closed_sphere_mesh(6, 10), "other");
  expect_error([&] { target->load(good, other); }, good.string(), "another scene");

  // A failed load leaves the object usable: rebuilt, it answers as brute force.
  target->build(scene);
  expect_matches_brute_force(*target, scene, random_rays(scene.bounds(), 200, 5), "after failed loads");
}

class Interface : public ConformanceTest {};

TEST_P(Interface, SaveLoadInsertRemoveNameTheStructure) {
  const Scene scene = Scene::from_mesh(closed_sphere_mesh(6, 8), "sphere");
  auto accel = build_checked(GetParam(), scene);
  const std::string file = (fs::temp_directory_path() / "rayaccel_never_written.bin").string();
  if (!accel->supports_save()) {
    expect_error([&] { accel->save(file); }, GetParam(), "does not support");
    expect_error([&] { accel->load(file, scene); }, GetParam(), "does not support");
  }
  if (!accel->supports_incremental()) {
    expect_error([&] { accel->insert(0); }, GetParam(), "does not support");
    expect_error([&] { accel->remove(0); }, GetParam(), "does not support");
  }
}

/// Insertion and removal through the interface (the octree): removed primitives are never hit, also after an
/// update() over moved vertices; inserted back, the answers are brute force's again.
class Incremental : public ConformanceTest {};

TEST_P(Incremental, InsertRemoveAndUpdateThroughTheInterface) {
  TriangleMesh mesh = closed_sphere_mesh(8, 10);
  Scene scene = Scene::from_mesh(mesh, "sphere");
  auto accel = build_checked(GetParam(), scene);
  const auto expect_removed_never_hit = [&](const std::string& label) {
    for (const Ray& ray : random_rays(scene.bounds(), 400, 9)) {
      const Hit hit = accel->intersect(ray);
      if (hit.found()) {
        EXPECT_NE(hit.prim_id % 2, 0u) << label << ": removed primitive hit: " << describe(ray);
      }
    }
  };
  for (std::uint32_t id = 0; id < scene.primitive_count(); id += 2) accel->remove(id);
  expect_removed_never_hit("removed");
  for (Vec3& v : mesh.vertices) v = Vec3{v.x * 0.8f, v.y + 0.1f * v.x, v.z};
  scene.set_vertices(mesh.vertices);
  EXPECT_EQ(accel->update(scene), UpdateKind::rebuilt);
  expect_removed_never_hit("removed, then updated");
  for (std::uint32_t id = 0; id < scene.primitive_count(); id += 2) accel->insert(id);
  EXPECT_TRUE(accel->validate().empty());
  expect_matches_brute_force(*accel, scene, random_rays(scene.bounds(), 400, 10), "reinserted");
}

INSTANTIATE_TEST_SUITE_P(Conformance, SaveLoad, ::testing::ValuesIn(specs_where(&Accelerator::supports_save, true)),
                         spec_test_name);
INSTANTIATE_TEST_SUITE_P(Conformance, Interface, ::testing::ValuesIn(variant_specs()), spec_test_name);
INSTANTIATE_TEST_SUITE_P(Conformance, Incremental,
                         ::testing::ValuesIn(specs_where(&Accelerator::supports_incremental, true)), spec_test_name);

}  // namespace
}  // namespace rayaccel::conformance
