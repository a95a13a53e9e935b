#include "d2vdb/io/SupportFunctionJson.h"

#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "IoTestSupport.h"
#include "d2vdb/support/SphericalTriangulation.h"

namespace d2vdb {
namespace {

SupportFunction someFunction(int degree) {
  std::mt19937 engine(5);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd c(harmonicCount(degree));
  for (Eigen::Index j = 0; j < c.size(); ++j) c[j] = uniform(engine) / (1.0 + j);
  c[0] = 3.0 + 1.0 / 3.0;
  return SupportFunction(degree, c);
}

TEST(SupportFunctionJson, SphereDomainRoundTripsBitForBit) {
  SupportFunctionDocument doc{
      someFunction(7), std::nullopt,
      SupportFitRecord{"ellipsoid \"a\".obj", 1234, 1e-10, 2.5e-5, 1.0 / 3.0}};
  const std::string text = supportFunctionToJson(doc);
  const SupportFunctionDocument back = parseSupportFunctionJson(text);
  ASSERT_EQ(back.function.degree(), 7);
  for (Eigen::Index j = 0; j < back.function.coefficients().size(); ++j) {
    EXPECT_TRUE(test::sameBits(back.function.coefficients()[j], doc.function.coefficients()[j]));
  }
  EXPECT_FALSE(back.patch.has_value());
  ASSERT_TRUE(back.fit.has_value());
  EXPECT_EQ(back.fit->source, "ellipsoid \"a\".obj");
  EXPECT_EQ(back.fit->samples, 1234u);
  EXPECT_TRUE(test::sameBits(back.fit->maxResidual, 1.0 / 3.0));
  EXPECT_EQ(supportFunctionToJson(back), text);
}

TEST(SupportFunctionJson, PatchDomainRoundTrips) {
  SphericalTriangulation patch = geodesicSphere(1);
  patch.triangles.resize(10);
  const SupportFunctionDocument doc{someFunction(3), patch, std::nullopt};
  const SupportFunctionDocument back = parseSupportFunctionJson(supportFunctionToJson(doc));
  ASSERT_TRUE(back.patch.has_value());
  EXPECT_EQ(back.patch->triangles, patch.triangles);
  ASSERT_EQ(back.patch->normals.size(), patch.normals.size());
  for (std::size_t i = 0; i < patch.normals.size(); ++i) {
    EXPECT_EQ(back.patch->normals[i], patch.normals[i]);
  }
  EXPECT_FALSE(back.fit.has_value());
}

TEST(SupportFunctionJson, RejectsMalformedDocumentsWithTheFieldPath) {
  const std::string good = supportFunctionToJson({someFunction(1), std::nullopt, std::nullopt});
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
  };
  using test::expectInputError;
  expectInputError([&] { parseSupportFunctionJson(replaced("\"version\": 1", "\"version\": 2")); },
                   {"version", "not supported"});
  expectInputError([&] { parseSupportFunctionJson(replaced("\"degree\": 1", "\"degree\": 2")); },
                   {"coefficients", "needs 9"});
  expectInputError([&] { parseSupportFunctionJson(replaced("\"degree\": 1", "\"degree\": 65")); },
                   {"degree", "not supported"});
  expectInputError(
      [&] { parseSupportFunctionJson(replaced("\"type\"", "\"colour\": 1, \"type\"")); },
      {"colour", "not a field"});
  expectInputError([&] { parseSupportFunctionJson(replaced("sphere", "cube")); },
                   {"domain.kind", "cube"});
  expectInputError(
      [&] { parseSupportFunctionJson(replaced("real_spherical_harmonics", "monomials")); },
      {"basis"});
  expectInputError([&] { parseSupportFunctionJson(good.substr(0, good.size() / 2)); },
                   {"invalid JSON"});
  std::string nullCoefficient = good;
  nullCoefficient.replace(nullCoefficient.find("[\n    ") + 6, 0, "null, ");
  expectInputError([&] { parseSupportFunctionJson(nullCoefficient); }, {"coefficients"});
  // Patch errors: out-of-range index, non-unit normal, unknown member.
  SphericalTriangulation patch = geodesicSphere(0);
  const std::string patchText = supportFunctionToJson({someFunction(1), patch, std::nullopt});
  std::string badIndex = patchText;
  badIndex.replace(badIndex.find("[0, 11, 5]"), 10, "[0, 12, 5]");
  expectInputError([&] { parseSupportFunctionJson(badIndex); },
                   {"domain.triangles[0][1]", "out of range"});
  std::string notUnit = patchText;
  const auto firstNormal = notUnit.find("[-0.");
  notUnit.replace(firstNormal, 4, "[-1.");
  expectInputError([&] { parseSupportFunctionJson(notUnit); }, {"domain.normals[0]", "unit"});
  std::string fitExtra =
      supportFunctionToJson({someFunction(1), std::nullopt, SupportFitRecord{"x", 1, 0, 0, 0}});
  fitExtra.replace(fitExtra.find("\"samples\""), 0, "\"seed\": 3, ");
  expectInputError([&] { parseSupportFunctionJson(fitExtra); }, {"fit.seed"});
}

}  // namespace
}  // namespace d2vdb
