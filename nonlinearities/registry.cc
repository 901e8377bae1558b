#include "nonlinearities/registry.h"

#include "core/input_fields.h"
#include "nonlinearities/coulomb_friction.h"
#include "nonlinearities/dlft_contact.h"
#include "nonlinearities/lcp_contact.h"
#include "nonlinearities/penalty_contact.h"
#include "nonlinearities/polynomial_spring.h"

namespace nfrc {

const std::map<std::string, NonlinearityFactory>& NonlinearityRegistry() {
  static const std::map<std::string, NonlinearityFactory> registry = {
      {"coulomb_friction", &CoulombFriction::FromJson},
      {"cubic_spring", &PolynomialSpring::CubicFromJson},
      {"dlft_contact", &DlftContact::FromJson},
      {"lcp_contact", &LcpContact::FromJson},
      {"penalty_contact", &PenaltyContact::FromJson},
      {"polynomial_spring", &PolynomialSpring::PolynomialFromJson},
  };
  return registry;
}

std::unique_ptr<Nonlinearity> MakeNonlinearity(const nlohmann::json& spec, const std::string& path,
                                               const LinearModel& model) {
  if (!spec.is_object()) throw InputError(path + ": expected an object");
  if (!spec.contains("type") || !spec.at("type").is_string()) {
    throw InputError(path + ".type: missing or not a string");
  }
  const std::string type = spec.at("type").get<std::string>();
  const auto& registry = NonlinearityRegistry();
  const auto found = registry.find(type);
  if (found == registry.end()) {
    std::string known;
    for (const auto& [name, factory] : registry) known += (known.empty() ? "" : ", ") + name;
    throw InputError(path + ".type: unknown nonlinearity \"" + type + "\" (known: " + known + ")");
  }
  return found->second(spec, path, model);
}

}  // namespace nfrc
