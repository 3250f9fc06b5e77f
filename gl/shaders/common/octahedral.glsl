// Octahedral normal encoding for the G-buffer (as in the clustered-shading
// thesis's deferred renderer): a unit normal maps onto the octahedron
// |x| + |y| + |z| = 1, the lower half folds over the diagonals onto the
// square [-1, 1]^2, and the two coordinates are stored in a 16-bit unorm RG
// target as e * 0.5 + 0.5. Mirrored in C++ by tests/gl/gbuffer_normal_test.cpp,
// which states the angular error of the 16-bit round trip.
vec2 octSign(vec2 v) { return vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0); }
vec2 octEncode(vec3 n) {
  vec2 p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
  if (n.z < 0.0) p = (1.0 - abs(p.yx)) * octSign(p);
  return p * 0.5 + 0.5;
}
vec3 octDecode(vec2 s) {
  vec2 e = s * 2.0 - 1.0;
  vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  float t = max(-n.z, 0.0);
  n.xy -= t * octSign(n.xy);
  return normalize(n);
}
