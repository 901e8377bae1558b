#include "tools/validate.h"

#include "tools/validation_writer.h"

namespace nfrc {

ValidationResult RunValidation(const Case& the_case, const ValidationSettings& settings,
                               const std::string& out_dir, std::ostream* progress,
                               std::ostream* table, const std::atomic<bool>* stop,
                               const nlohmann::json& source) {
  ValidationWriter writer(out_dir, the_case, settings, source, table);
  ValidationOptions options;
  options.progress = progress;
  options.stop = stop;
  options.observer = &writer;
  return ValidateCase(the_case, settings, options);
}

}  // namespace nfrc
