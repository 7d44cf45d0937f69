/**
 * @file ident_apply.c
 * @brief The identification run's results into the motor model (dtc/ident_apply.h).
 */
#include "dtc/ident_apply.h"

#include "dtc/ratings_types.h"

static bool ident_ok(const ident_value *v) { return v->verdict == IDENT_VERDICT_OK; }

int ident_apply(const ident *s, const ident_result *r, const ctl_cfg *from, ctl_cfg *to)
{
    *to = *from;
    if (s->phase != IDENT_DONE && s->phase != IDENT_WAIT_APPLY)
        return IDENT_E_PHASE;
    motor_model *m = &to->motor;
    int applied = 0;
    if (ident_ok(&r->rs_ohm)) {
        m->Rs_ohm = r->rs_ohm.value;
        ratings_mask_set(&to->set, RATINGS_ID_MOTOR_RS);
        /* the run's DC steps account for the dead time and the device drops; the
         * quick estimate while magnetising does not (it read the 50 hp motor's Rs
         * 39 % high with 2 us of dead time) and must not replace the measured value */
        to->rs_ident_tol = R(1.0);
        applied |= IDENT_APPLIED_RS;
    }
    if (ident_ok(&r->lm_H) && ident_ok(&r->ls_H) && ident_ok(&r->rr_ohm) && ident_ok(&r->sigma_ls_H)) {
        m->Lm_H = r->lm_H.value;
        m->Ls_H = r->ls_H.value;
        m->Lr_H = r->ls_H.value; /* equal leakages (dtc/ident_fit.h, ident_t_model) */
        m->Rr_ohm = r->rr_ohm.value;
        ratings_mask_set(&to->set, RATINGS_ID_MOTOR_LM);
        ratings_mask_set(&to->set, RATINGS_ID_MOTOR_LS);
        ratings_mask_set(&to->set, RATINGS_ID_MOTOR_LR);
        ratings_mask_set(&to->set, RATINGS_ID_MOTOR_RR);
        applied |= IDENT_APPLIED_MAGNETICS;
    }
    if (s->phase == IDENT_DONE && ident_ok(&r->j_kgm2)) {
        m->J_kgm2 = r->j_kgm2.value;
        ratings_mask_set(&to->set, RATINGS_ID_MOTOR_J);
        applied |= IDENT_APPLIED_J;
    }
    if (s->phase == IDENT_DONE && ident_ok(&r->b_Nms)) {
        m->B_Nms = r->b_Nms.value;
        ratings_mask_set(&to->set, RATINGS_ID_MOTOR_B);
        applied |= IDENT_APPLIED_B;
    }
    /* an identified value is no longer the plate's estimate: marked set, so that
     * the re-derivation (and every later commit) keeps it and derives from it */
    (void)ctl_cfg_rederive(to);
    if (ctl_cfg_check(to) != CTL_CFG_OK) {
        *to = *from;
        return IDENT_E_REJECTED;
    }
    return applied;
}
