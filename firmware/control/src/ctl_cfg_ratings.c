/**
 * @file ctl_cfg_ratings.c
 * @brief The default configuration from the reference drive's ratings, and
 *        the commit's derivation from the plate (dtc/ctl_cfg.h). Context: BG.
 *
 * Apart from ctl_cfg.c because it calls the derivation (ratings.c), which
 * calls ctl_cfg_derive: the files stay a chain, not a cycle.
 */
#include "dtc/ctl_cfg.h"

#include <string.h>

#include "dtc/ratings.h"

void ctl_cfg_default(ctl_cfg *cfg)
{
    ctl_cfg_fixed_default(cfg);
    ratings_reference(&cfg->plate, &cfg->motor);
    /* the 10 hp motor's own model is known (docs/motor-10hp.json): set, as an
     * identification would leave it; everything else derived */
    memset(&cfg->set, 0, sizeof cfg->set);
    for (int id = RATINGS_ID_MOTOR_RS; id <= RATINGS_ID_MOTOR_B; id++)
        ratings_mask_set(&cfg->set, (ratings_id)id);
    cfg->from_plate = true;
    if (!ctl_cfg_rederive(cfg))
        ctl_cfg_derive(cfg); /* not reached: the reference plate passes (tests/unit/test_ratings.cpp) */
}

bool ctl_cfg_rederive(ctl_cfg *cfg)
{
    if (cfg->from_plate) {
        ratings plate = cfg->plate;
        ratings_mask set = cfg->set;
        if (ratings_derive_cfg(cfg, &plate, &set).reason == RATINGS_OK)
            return true;
        ctl_cfg_derive(cfg);
        return false;
    }
    ctl_cfg_derive(cfg);
    return true;
}
