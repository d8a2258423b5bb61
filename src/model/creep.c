/* The linear wheel-rail contact terms of one wheelset (docs/model.md section
 * 3): Kalker's linear creep theory with the longitudinal and lateral creep
 * coefficients f11, f22 (J. J. Kalker, "On the rolling contact of two
 * elastic bodies in the presence of dry friction", Delft 1967; the linear
 * wheelset as in A. H. Wickens, Fundamentals of Rail Vehicle Dynamics, 2003,
 * chapter 2), the equivalent conicity lambda and, optionally, the
 * gravitational stiffness of the normal forces. The one home of these
 * formulas: the model adds them at each operating point. */
#include "model/model_impl.h"

/* At speed v (m/s) and conicity lambda, for lateral motion y and yaw psi:
   F_y = -2 f22 (y'/v - psi)                       -> cy = 2 f22 / v, kyp = -2 f22
   M_z = -2 f11 l0 (l0 psi'/v + lambda (y - y_t)/r0) -> cp = 2 f11 l0^2 / v,
                                                     kpy = 2 f11 l0 lambda / r0
   gravity: F_y += -(W lambda / l0)(y - y_t), M_z += W lambda l0 psi. */
rr_creep_terms rr_creep_terms_at(const rr_contact_spec *s, double v, double lambda, int gravity)
{
  rr_creep_terms t = {.cy = 2 * s->f22 / v,
                      .cp = 2 * s->f11 * s->l0 * s->l0 / v,
                      .kyp = -2 * s->f22,
                      .kpy = 2 * s->f11 * s->l0 * lambda / s->r0};
  if (gravity) {
    double W = s->axle_load;
    t.gy = W * lambda / s->l0;
    t.gpsi = W * lambda * s->l0;
  }
  return t;
}
