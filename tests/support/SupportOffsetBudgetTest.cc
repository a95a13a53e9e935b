// The budget of support-function offsets: the domain sizes the estimates use against the
// geodesic spheres really built, and the refusal naming the largest --subdivisions that fits.
#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "d2vdb/core/Error.h"
#include "d2vdb/support/SphericalTriangulation.h"
#include "d2vdb/support/SupportOffsets.h"

namespace d2vdb {
namespace {

TEST(SupportOffsetBudget, DomainSizesAreThoseOfTheDomainsBuilt) {
  for (int s = 0; s <= 4; ++s) {
    const SphericalTriangulation sphere = tessellationDomain(std::nullopt, s);
    const auto [vertices, triangles] = tessellationDomainSize(std::nullopt, s);
    EXPECT_EQ(vertices, static_cast<double>(sphere.normals.size())) << s;
    EXPECT_EQ(triangles, static_cast<double>(sphere.triangles.size())) << s;
    // A patch's own domain counts, whatever the subdivisions.
    const auto patch = tessellationDomainSize(sphere, 9);
    EXPECT_EQ(patch[0], vertices);
    EXPECT_EQ(patch[1], triangles);
  }
}

TEST(SupportOffsetBudget, RefusesNamingTheSubdivisionsThatFit) {
  ResourceBudget budget;  // defaults: two OBJ offsets at 9 subdivisions are about 2 x 0.6 GB
  EXPECT_NO_THROW(enforceSupportOffsetBudget(std::nullopt, 7, 2, MeshFormat::Obj, 0.0, budget));
  try {
    enforceSupportOffsetBudget(std::nullopt, 9, 2, MeshFormat::Obj, 0.0, budget);
    FAIL() << "no error";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("--subdivisions 9"), std::string::npos) << message;
    EXPECT_NE(message.find("use --subdivisions 8 or fewer"), std::string::npos) << message;
    EXPECT_NE(message.find("--max-output"), std::string::npos) << message;
  }
  // Level-set outputs write no mesh: only the memory counts.
  budget.maxMemoryBytes = 1'000'000'000;
  try {
    enforceSupportOffsetBudget(std::nullopt, 9, 1, std::nullopt, 250.0, budget);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("--max-memory"), std::string::npos) << error.what();
  }
  budget.maxMemoryBytes = 0;  // no limit
  EXPECT_NO_THROW(enforceSupportOffsetBudget(std::nullopt, 9, 1, std::nullopt, 250.0, budget));
}

}  // namespace
}  // namespace d2vdb
