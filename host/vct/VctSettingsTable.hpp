#pragma once
// The settings of `--gi vct` as one table (key, help, type, getter, parser):
// `render`'s flags are registered from it (--KEY, host/app/GiOptions) and the
// viewer's GI panel and `gi_param` script action set the same keys through it,
// so both parse the same way and are checked by the one validation,
// checkVctGiSettings (host/vct/VctGiPass.hpp).
//  - parseVctSetting(): the value into `s` (no range check: a flag's range can
//    depend on another, e.g. --levels on --voxels); UserError naming --KEY when
//    the text is not of the setting's type, or the key is unknown.
//  - withVctSetting(): parse into a copy, then checkVctGiSettings on the whole.
#include <string>
#include <vector>

#include "host/vct/VctGiPass.hpp"

namespace ml::vct {

enum class VctSettingType { Count, Number, Switch, Choice };

struct VctSetting {
  std::string key;  // "voxels": the flag --voxels, the viewer's gi_param key
  std::string help;
  VctSettingType type;
  std::vector<std::string> choices;  // Choice only
  std::string (*get)(const VctGiSettings&);
  void (*set)(VctGiSettings&, const std::string& key, const std::string& text);
  std::string flag() const { return "--" + key; }
};

const std::vector<VctSetting>& vctSettings();
void parseVctSetting(VctGiSettings& s, const std::string& key, const std::string& text);
VctGiSettings withVctSetting(VctGiSettings s, const std::string& key, const std::string& text);

}  // namespace ml::vct
