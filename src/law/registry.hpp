#pragma once
// Constitutive laws by name (docs/developer-guide.md §5: one registry per category, string-keyed, with a
// loud error naming the valid keys). A law declares its parameters and its state
// variables; the scenario schema, docs/scenario-reference.md, the per-item state arrays,
// checkpoints and VTU fields all come from these declarations, not from central lists.
// This module sits below io/, mesh/ and solver/ and depends on the standard library only.
#include <cstddef>
#include <functional>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace dsdem::law {

enum class Category { Material, Joint, Contact };
const char* category_name(Category c);  // "material", "joint", "contact"

struct LawDecl;

// One scalar parameter of a law, as the scenario gives it (values in `unit`).
struct ParamDecl {
  std::string name;          // scenario key, e.g. "cohesion"
  std::string unit;          // SI unit text, "" when dimensionless
  std::string default_text;  // "required", a number, a rule ("c / tan(phi)"), or "" (none)
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;
  bool max_exclusive = false;
  std::string doc;
  // A contact parameter that contact.pairs[] may set for one pair of surface groups.
  bool per_pair = false;
  // The default when default_text is a rule: computed from the parameters declared before
  // this one (values in declaration order). Empty when the caller applies the rule itself.
  std::function<double(const LawDecl&, std::span<const double>)> rule;
  bool required() const { return default_text == "required"; }
};

// One state variable: one double per item (triangle, joint, contact), zero initially.
struct StateDecl {
  std::string name;  // output and checkpoint name, e.g. "plastic_strain_xx"
  std::string unit;  // SI unit text, "" when dimensionless
  std::string doc;
};
// A state variable as a constant table holds it (a kernel's header may share the table).
struct StateVariable {
  const char* name;
  const char* unit;
  const char* doc;
};

// How strength reduction treats tension (docs/theory.md §9).
struct ReductionOptions {
  bool keep_tension = false;  // tensile strengths are not divided by F
};

// A problem found by a law's cross-check of its parameter values.
struct ParamProblem {
  std::string param;  // the parameter at fault
  std::string message;
};

struct LawDecl {
  Category category = Category::Material;
  std::string name;
  std::string doc;
  std::vector<ParamDecl> params;
  std::vector<StateDecl> state;
  // State the law's own module keeps in arrays of its own shape (e.g. two points per
  // joint), named for the reference only; "" when there is none or all is in `state`.
  std::string module_state;
  // Whether the law admits plane stress (mesh.plane: stress); else plane strain only.
  bool plane_stress = true;
  // Checks that involve several parameters (e.g. dilation <= friction angle), run on the
  // values in declaration order once all are read; empty when there are none.
  std::function<std::vector<ParamProblem>(const LawDecl&, std::span<const double>)> check;
  // Strength reduction by a trial factor F (docs/theory.md §9): the parameter values with
  // each of the law's strengths divided by F, from the full values (declaration order);
  // the stiffnesses stay. Empty for a law without a strength, which stays as it is.
  std::function<std::vector<double>(const LawDecl&, std::span<const double> full, double F, const ReductionOptions&)>
      reduce;

  // Index of a parameter in declaration order, or -1.
  int param_index(std::string_view param) const;
  // The value of a declared parameter; throws std::logic_error for an undeclared one.
  double value(std::span<const double> values, std::string_view param) const;
  bool has_param(std::string_view param) const { return param_index(param) >= 0; }
};

// An unknown law name: the message names the category and every valid name.
class UnknownLaw : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

class Registry {
 public:
  explicit Registry(Category category) : category_(category) {}
  // Registers a law; throws std::logic_error on a duplicate name or a wrong category.
  Registry& add(LawDecl decl);
  // The law of that name; throws UnknownLaw naming the valid ones.
  const LawDecl& get(std::string_view name) const;
  const LawDecl* find(std::string_view name) const;
  int index(std::string_view name) const;  // registration order, or -1
  const LawDecl& at(std::size_t i) const { return laws_.at(i); }
  std::size_t size() const { return laws_.size(); }
  const std::vector<LawDecl>& laws() const { return laws_; }
  std::vector<std::string> names() const;
  Category category() const { return category_; }

 private:
  Category category_;
  std::vector<LawDecl> laws_;
};

// The registries, filled on first use (registry.cpp: one line per law).
const Registry& material_laws();
const Registry& joint_laws();
const Registry& contact_laws();
const Registry& registry(Category c);

// The default law of each category: the one every scenario had before laws were named.
inline constexpr std::string_view kDefaultMaterialLaw = "linear_elastic";
inline constexpr std::string_view kDefaultJointLaw = "cohesive";
inline constexpr std::string_view kDefaultContactLaw = "spring_dashpot_coulomb";

}  // namespace dsdem::law
