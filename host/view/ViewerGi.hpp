#pragma once
// The viewer's global illumination: none or a registered GI pass
// (host/gi/Registry.hpp; the frame's GiPass), its parameters set by key as
// render's flags of that pass are (giParams: each value against its spec,
// then the whole set), its view parameters likewise (giViewParams), and its
// two view modes: the indirect light (as render's <out>_gi_NAME.png) and the
// pass's own view (GiPass::view, e.g. the voxel volume, as render's view
// flags write it). A refused value (unknown key, bad text, a set the pass
// rejects, a pass that cannot be built) throws UserError and leaves the last
// working state in place. After a parameter change the view values are
// brought back in range (the descriptor's fit_view: e.g. the shown voxel
// level follows --levels down). One pass is selected even while GI is off
// (at first the registry's first): its parameters can be set then and are
// used when it is turned on. Parameters given for a pass are kept per pass,
// so switching passes and back restores them.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "gl/GiDescriptor.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/scene/Camera.hpp"
#include "host/scene/Scene.hpp"

namespace ml {

class ViewerGi {
 public:
  ViewerGi(ClRuntime& cl, const Scene& scene);
  ~ViewerGi();

  void setMode(const std::string& mode);  // none | a registered GI pass
  void setParam(const std::string& key, const std::string& value);
  void setView(const std::string& key, const std::string& value);  // a view parameter of the pass

  bool on() const { return pass_ != nullptr; }
  const std::string& mode() const { return mode_; }
  const GiDescriptor& descriptor() const { return *descriptor_; }  // the selected pass, on or off
  // The selected pass's parameters and view values (its defaults when none was given).
  const ParamValues& params() const { return params_; }
  const ParamValues& view() const { return view_; }
  GiPass* pass() { return pass_.get(); }  // null when none

  // Of the last frame rendered with pass(): displayed RGBA, rows bottom-up.
  std::vector<float> indirectImage() const;
  std::vector<float> viewImage(const Camera& camera, unsigned width, unsigned height);

 private:
  void select(const GiDescriptor& d, bool build);
  void rebuild(const ParamValues& params);

  ClRuntime& cl_;
  const Scene& scene_;
  std::string mode_ = "none";
  const GiDescriptor* descriptor_;
  std::map<std::string, SettingList> given_, view_given_;  // per pass name, as set (the last value per key wins)
  ParamValues params_, view_;
  std::unique_ptr<GiPass> pass_;
};

}  // namespace ml
