#include "law/registry.hpp"

#include <fmt/format.h>

#include "law/laws.hpp"

namespace dsdem::law {

const char* category_name(Category c) {
  switch (c) {
    case Category::Material: return "material";
    case Category::Joint: return "joint";
    case Category::Contact: return "contact";
  }
  return "?";
}

int LawDecl::param_index(std::string_view param) const {
  for (std::size_t i = 0; i < params.size(); ++i)
    if (params[i].name == param) return static_cast<int>(i);
  return -1;
}

double LawDecl::value(std::span<const double> values, std::string_view param) const {
  const int i = param_index(param);
  if (i < 0 || static_cast<std::size_t>(i) >= values.size())
    throw std::logic_error(fmt::format("{} law '{}' has no parameter '{}'", category_name(category), name, param));
  return values[static_cast<std::size_t>(i)];
}

Registry& Registry::add(LawDecl decl) {
  if (decl.category != category_)
    throw std::logic_error(fmt::format("law '{}' is a {} law, not a {} law", decl.name, category_name(decl.category),
                                       category_name(category_)));
  if (find(decl.name)) throw std::logic_error(fmt::format("{} law '{}' registered twice", category_name(category_), decl.name));
  laws_.push_back(std::move(decl));
  return *this;
}

const LawDecl* Registry::find(std::string_view name) const {
  for (const auto& l : laws_)
    if (l.name == name) return &l;
  return nullptr;
}

int Registry::index(std::string_view name) const {
  for (std::size_t i = 0; i < laws_.size(); ++i)
    if (laws_[i].name == name) return static_cast<int>(i);
  return -1;
}

std::vector<std::string> Registry::names() const {
  std::vector<std::string> out;
  for (const auto& l : laws_) out.push_back(l.name);
  return out;
}

const LawDecl& Registry::get(std::string_view name) const {
  if (const LawDecl* l = find(name)) return *l;
  std::string list;
  for (const auto& l : laws_) list += (list.empty() ? "" : ", ") + l.name;
  throw UnknownLaw(fmt::format("unknown {} law '{}'; the {} laws are: {}", category_name(category_), name,
                               category_name(category_), list));
}

// Registration: one line per law. Explicit lists, not self-registering statics, which a
// static library's linker may drop. The first law of each list is the default one.
const Registry& material_laws() {
  static const Registry r = Registry(Category::Material)
                                .add(linear_elastic_decl())
                                .add(mohr_coulomb_decl())
                                .add(drucker_prager_decl());
  return r;
}

const Registry& joint_laws() {
  static const Registry r = Registry(Category::Joint)
                                .add(cohesive_joint_decl());
  return r;
}

const Registry& contact_laws() {
  static const Registry r = Registry(Category::Contact)
                                .add(spring_dashpot_coulomb_decl());
  return r;
}

const Registry& registry(Category c) {
  switch (c) {
    case Category::Material: return material_laws();
    case Category::Joint: return joint_laws();
    case Category::Contact: return contact_laws();
  }
  throw std::logic_error("unknown law category");
}

}  // namespace dsdem::law
