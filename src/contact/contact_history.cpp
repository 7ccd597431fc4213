#include "contact/contact_history.hpp"

#include <algorithm>

namespace dsdem::contact {

Vec2 ContactHistory::previous(const ContactKey& key) const {
  const auto it = std::lower_bound(previous_.begin(), previous_.end(), key,
                                   [](const Entry& e, const ContactKey& k) { return e.key < k; });
  if (it != previous_.end() && it->key == key) return it->ft;
  return Vec2::Zero();
}

}  // namespace dsdem::contact
