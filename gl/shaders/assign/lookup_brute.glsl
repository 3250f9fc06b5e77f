// Brute force: every light for every shaded point.
struct LightList {
  uint offset;
  uint count;
};
LightList lightListFor(vec3 world_pos, vec3 view_pos, vec2 frag_coord) { return LightList(0u, u_light_count); }
bool listEnded(LightList list) { return list.count == 0u; }
bool nextLight(inout LightList list, out uint light_index) {
  light_index = list.offset;
  if (list.count == 0u) return false;
  ++list.offset;
  --list.count;
  return true;
}
