// Irradiance from the sky's 9 SH coefficients (Ramamoorthi & Hanrahan 2001, Eq. 13), for the
// per-splat ambient term and the per-pixel one of the pixel-AO mode.
uniform vec3 u_sh[9];  // irradiance SH of the sky
vec3 sh_irradiance(vec3 n) {
  const float c1 = 0.429043, c2 = 0.511664, c3 = 0.743125, c4 = 0.886227, c5 = 0.247708;
  return c1 * u_sh[8] * (n.x * n.x - n.y * n.y) + c3 * u_sh[6] * n.z * n.z + c4 * u_sh[0] - c5 * u_sh[6]
       + 2.0 * c1 * (u_sh[4] * n.x * n.y + u_sh[7] * n.x * n.z + u_sh[5] * n.y * n.z)
       + 2.0 * c2 * (u_sh[3] * n.x + u_sh[1] * n.y + u_sh[2] * n.z);
}
