/* The layout of the public structs that bindings mirror (the Python
 * package checks its ctypes copies against it at import, so that a change on
 * the C side cannot silently misread memory). */
#include <stddef.h>
#include <string.h>
#include "railride/railride.h"

typedef struct layout_entry {
  const char *type, *field; /* field NULL: the type itself */
  size_t offset, size;
} layout_entry;

#define TYPE(t)                                                                                    \
  {                                                                                                \
#t, NULL, 0, sizeof(t)                                                                         \
  }
#define FIELD(t, f)                                                                                \
  {                                                                                                \
#t, #f, offsetof(t, f), sizeof(((t *)0)->f)                                                    \
  }

static const layout_entry layout[] = {
    TYPE(rr_error),
    FIELD(rr_error, code),
    FIELD(rr_error, msg),
    TYPE(rr_modal_opts),
    FIELD(rr_modal_opts, fmax_hz),
    FIELD(rr_modal_opts, w_min),
    FIELD(rr_modal_opts, r_max),
    FIELD(rr_modal_opts, tracking),
    TYPE(rr_mode),
    FIELD(rr_mode, re),
    FIELD(rr_mode, im),
    FIELD(rr_mode, freq_hz),
    FIELD(rr_mode, zeta),
    FIELD(rr_mode, energy),
    FIELD(rr_mode, roll_share),
    FIELD(rr_mode, frame_roll_share),
    FIELD(rr_mode, oscillatory),
    FIELD(rr_mode, hunting),
    FIELD(rr_mode, in_index),
    FIELD(rr_mode, self_consistent),
    FIELD(rr_mode, sdf_k),
    FIELD(rr_mode, name),
    TYPE(rr_modal_result),
    FIELD(rr_modal_result, n),
    FIELD(rr_modal_result, cap),
    FIELD(rr_modal_result, modes),
    FIELD(rr_modal_result, ndof),
    FIELD(rr_modal_result, shapes),
    FIELD(rr_modal_result, stability_index),
    FIELD(rr_modal_result, index_mode),
    FIELD(rr_modal_result, index_source),
    FIELD(rr_modal_result, hunting_index),
    FIELD(rr_modal_result, hunting_mode),
    FIELD(rr_modal_result, zeta_max),
    FIELD(rr_modal_result, max_mode),
    TYPE(rr_stability),
    FIELD(rr_stability, index),
    FIELD(rr_stability, index_freq_hz),
    FIELD(rr_stability, source),
    FIELD(rr_stability, hunting_index),
    FIELD(rr_stability, zeta_max),
    FIELD(rr_stability, max_freq_hz),
    TYPE(rr_robust_opts),
    FIELD(rr_robust_opts, v_low_ms),
    FIELD(rr_robust_opts, conicity_low),
    FIELD(rr_robust_opts, v_high_ms),
    FIELD(rr_robust_opts, conicity_high),
    FIELD(rr_robust_opts, conicity_min),
    FIELD(rr_robust_opts, conicity_max),
    FIELD(rr_robust_opts, n_conicity),
    TYPE(rr_robust),
    FIELD(rr_robust, zeta_low),
    FIELD(rr_robust, zeta_high),
    FIELD(rr_robust, std_zeta),
    FIELD(rr_robust, zeta_max),
    FIELD(rr_robust, n_unstable),
    FIELD(rr_robust, unstable_speed_ms),
    FIELD(rr_robust, unstable_conicity),
    TYPE(rr_critical_opts),
    FIELD(rr_critical_opts, v_min_ms),
    FIELD(rr_critical_opts, v_max_ms),
    FIELD(rr_critical_opts, step_ms),
    FIELD(rr_critical_opts, tol_ms),
    FIELD(rr_critical_opts, index_modes),
    TYPE(rr_critical),
    FIELD(rr_critical, found),
    FIELD(rr_critical, speed_ms),
    FIELD(rr_critical, mode),
    TYPE(rr_frf_opts),
    FIELD(rr_frf_opts, nfreq),
    FIELD(rr_frf_opts, freqs_hz),
    FIELD(rr_frf_opts, f_lo_hz),
    FIELD(rr_frf_opts, f_hi_hz),
    FIELD(rr_frf_opts, npoints),
    FIELD(rr_frf_opts, rows),
    FIELD(rr_frf_opts, rows0),
    FIELD(rr_frf_opts, method),
    TYPE(rr_comfort),
    FIELD(rr_comfort, rms),
    FIELD(rr_comfort, sperling),
    FIELD(rr_comfort, sperling_gb),
    FIELD(rr_comfort, wd_rms),
    TYPE(rr_polyline),
    FIELD(rr_polyline, n),
    FIELD(rr_polyline, x),
    FIELD(rr_polyline, z),
    TYPE(rr_contact_opts),
    FIELD(rr_contact_opts, gauge_mm),
    FIELD(rr_contact_opts, flange_back_mm),
    FIELD(rr_contact_opts, wheel_origin_mm),
    FIELD(rr_contact_opts, inclination),
    FIELD(rr_contact_opts, gmp_depth_mm),
    FIELD(rr_contact_opts, gmp_right_mm),
    FIELD(rr_contact_opts, gmp_left_mm),
    FIELD(rr_contact_opts, lateral_offset_mm),
    FIELD(rr_contact_opts, r0_right_mm),
    FIELD(rr_contact_opts, r0_left_mm),
    FIELD(rr_contact_opts, roll),
    TYPE(rr_contact_side),
    FIELD(rr_contact_side, rail_v_mm),
    FIELD(rr_contact_side, rail_z_mm),
    FIELD(rr_contact_side, wheel_u_mm),
    FIELD(rr_contact_side, wheel_z_mm),
    FIELD(rr_contact_side, r_mm),
    FIELD(rr_contact_side, gamma_rad),
    FIELD(rr_contact_side, lift_mm),
    FIELD(rr_contact_side, valid),
    TYPE(rr_contact_state),
    FIELD(rr_contact_state, y_mm),
    FIELD(rr_contact_state, dr_mm),
    FIELD(rr_contact_state, roll_rad),
    FIELD(rr_contact_state, roll_implied_rad),
    FIELD(rr_contact_state, side),
    FIELD(rr_contact_state, valid),
    TYPE(rr_conicity),
    FIELD(rr_conicity, amplitude_mm),
    FIELD(rr_conicity, tan_gamma_e),
    FIELD(rr_conicity, turning_mm),
    FIELD(rr_conicity, energy),
    FIELD(rr_conicity, wavelength_mm),
    FIELD(rr_conicity, tan_gamma_e_harmonic),
    FIELD(rr_conicity, harmonic_centre_mm),
    FIELD(rr_conicity, tan_gamma_e_regression),
};

int rr_layout(const char *type, const char *field, size_t *offset, size_t *size)
{
  for (size_t i = 0; i < sizeof layout / sizeof layout[0]; i++) {
    const layout_entry *e = &layout[i];
    if (strcmp(e->type, type) || (field ? !e->field || strcmp(e->field, field) : e->field != NULL))
      continue;
    if (offset) *offset = e->offset;
    if (size) *size = e->size;
    return RR_OK;
  }
  return RR_EINVAL;
}
