// The bulk laws' kernels (fem/bulk_law.hpp): every declared material law has its kernel,
// the kernel holds the state its declaration names, and a material dispatches to the
// kernel of its law with that kernel's bits.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>

#include "fem/bulk_law.hpp"
#include "law/laws.hpp"
#include "model/model.hpp"

using namespace dsdem;

namespace {

fem::ElasticConstants constants() {
  Material m;
  m.E = 1e8;
  m.nu = 0.3;
  return {m.lambda(), m.mu()};
}

// Admissible values of a law's parameters: the declared defaults, 1 where one is required
// (angles 30 deg), the rules applied.
std::vector<double> sample_params(const law::LawDecl& decl) {
  std::vector<double> v;
  for (const auto& p : decl.params) {
    double x = 1.0;
    if (p.rule) x = p.rule(decl, v);
    else if (!p.required() && !p.default_text.empty()) x = std::stod(p.default_text);
    else if (p.unit == "deg") x = 30.0;
    else if (p.name == "nu") x = 0.3;
    v.push_back(x);
  }
  return v;
}

}  // namespace

TEST(BulkLaw, EveryDeclaredMaterialLawHasItsKernel) {
  for (const auto& decl : law::material_laws().laws()) {
    SCOPED_TRACE(decl.name);
    const fem::BulkLaw law = fem::make_bulk_law(decl, sample_params(decl), constants(), false);
    EXPECT_EQ(law.name(), decl.name);
    EXPECT_EQ(law.state_size(), decl.state.size());
    const int k = law.dissipation();
    if (decl.state.empty()) {
      EXPECT_EQ(k, -1);
    } else {  // the accumulated dissipation the energy ledger sums
      ASSERT_GE(k, 0);
      EXPECT_EQ(decl.state[static_cast<std::size_t>(k)].unit, "J/m^3");
    }
  }
}

TEST(BulkLaw, ALawWithoutAKernelOrWithOtherStateIsALogicError) {
  law::LawDecl orphan = law::mohr_coulomb_decl();
  orphan.name = "orphan";
  EXPECT_THROW(fem::make_bulk_law(orphan, sample_params(orphan), constants(), false), std::logic_error);
  law::LawDecl shorter = law::mohr_coulomb_decl();
  shorter.state.pop_back();
  EXPECT_THROW(fem::make_bulk_law(shorter, sample_params(shorter), constants(), false), std::logic_error);
}
