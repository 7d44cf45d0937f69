/**
 * @file npc_plan_leg.c
 * @brief Test oracle: one NPC leg's plan per period (see npc_plan_leg.h).
 */
#include "npc_plan_leg.h"

#include "npc_plan_rules.h"

/* The rules (npc_plan_rules.h) per (prev, v0, v1), written out by the preprocessor. */
#define EV(F, p, a, b)                                          \
    {{F(0u, NPC_AT_ZERO, p, a, b), F(1u, NPC_AT_ZERO, p, a, b)}, \
     {F(0u, NPC_AT_T, p, a, b), F(1u, NPC_AT_T, p, a, b)},       \
     {F(0u, NPC_AT_PER, p, a, b), F(1u, NPC_AT_PER, p, a, b)}}
#define RULE(p, a, b)                                                                               \
    {(uint8_t)NPC_RULE_V0(p, a), (uint8_t)NPC_RULE_V1(p, a, b), (uint8_t)NPC_RULE_FIXUPS(p, a, b), \
     (uint8_t)(NPC_LEG_PN(p, NPC_RULE_V1(p, a, b)) ? 0u : 1u), EV(NPC_RULE_SET, p, a, b), EV(NPC_RULE_RST, p, a, b)}
#define RULES_B(p, a) RULE(p, a, 0u), RULE(p, a, 1u), RULE(p, a, 2u)
#define RULES_A(p) RULES_B(p, 0u), RULES_B(p, 1u), RULES_B(p, 2u)

const npc_leg_rule npc_leg_rules[27] = {RULES_A(0u), RULES_A(1u), RULES_A(2u)};

void npc_plan_leg_at(const npc_timing *tm, const npc_instants *in, uint8_t prev, uint8_t v0, uint8_t v1,
                     npc_leg_plan *out)
{
    const npc_leg_rule *r = &npc_leg_rules[9u * prev + 3u * v0 + v1];
    uint32_t t = r->v0 == r->v1 ? tm->per : (r->may_drop != 0u ? in->drop : in->keep);
    unsigned c = t == 0u ? (unsigned)NPC_AT_ZERO : (t == tm->per ? (unsigned)NPC_AT_PER : (unsigned)NPC_AT_T);
    out->set[0] = r->set[c][0];
    out->set[1] = r->set[c][1];
    out->rst[0] = r->rst[c][0];
    out->rst[1] = r->rst[c][1];
    out->t = t;
    out->v0 = r->v0;
    out->v1 = r->v1;
    out->end = c == (unsigned)NPC_AT_PER ? r->v0 : r->v1;
    out->fixups = r->fixups;
}

void npc_plan_leg(const npc_timing *tm, uint8_t prev, uint8_t v0, uint8_t v1, uint32_t t0, npc_leg_plan *out)
{
    npc_instants in;
    npc_instants_of(tm, t0, &in);
    npc_plan_leg_at(tm, &in, prev, v0, v1, out);
}

bool npc_pair_level(unsigned pair, uint8_t leg) { return NPC_RULE_LEVEL(pair, leg); }
