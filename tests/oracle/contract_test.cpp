// contract_test.cpp — the shared contract checker (rayproof/oracle/contract.hpp) against
// hand-made answers: it accepts what each mode is allowed to answer and rejects each kind
// of breach (a false miss or a short interval in conservative mode, a wrong verdict, a
// wrong face or a t that is not faithful in certified mode, a validity mismatch in any
// mode, a NaN t, an interval outside [t_min, t_max], a face out of range), and reports
// the first breach in the order the fuzz targets print. Also the tally of judgements.
#include <rayproof/oracle/contract.hpp>
#include <rayproof/oracle/oracle.hpp>
#include <rayproof/rayproof.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

namespace {

using namespace rayproof;
using oracle::Breach;
using oracle::ContractCheck;
using oracle::ModeId;

using detail::step_down;
using detail::step_up;

// Ray (-1, 1/2, 1/2) + t·(3, 0, 0) against [0, 1]³: exactly [1/3, 2/3], entering through
// face 0 (the -x side).
const Ray<double> kRay{{-1, 0.5, 0.5}, {3, 0, 0}};
const Aabb<double> kBox{{0, 0, 0}, {1, 1, 1}};
// The same ray against a box it misses.
const Aabb<double> kFarBox{{0, 4, 4}, {1, 5, 5}};

Hit<double> hit(double t_enter, double t_exit, int face) { return {Verdict::hit, t_enter, t_exit, face}; }
Hit<double> answer(Verdict v) {
    Hit<double> h;
    h.verdict = v;
    return h;
}

// The faithful roundings of 1/3 and 2/3 in double.
double third_lo() { return oracle::exact(kRay, kBox).enter_bracket().lo; }
double third_hi() { return oracle::exact(kRay, kBox).enter_bracket().hi; }
double two_thirds_lo() { return oracle::exact(kRay, kBox).exit_bracket().lo; }
double two_thirds_hi() { return oracle::exact(kRay, kBox).exit_bracket().hi; }

template <class Shape, class Mode> ContractCheck check(const Shape& shape, const Hit<double>& h, Mode mode) {
    return oracle::check_contract(kRay, shape, h, oracle::exact(kRay, shape), mode);
}

TEST(ContractCheck, TheExactAnswerPassesEveryMode) {
    const auto h = hit(third_lo(), two_thirds_hi(), 0);
    EXPECT_TRUE(check(kBox, h, certified).ok());
    EXPECT_TRUE(check(kBox, hit(third_hi(), two_thirds_lo(), 0), certified).ok());  // the other roundings
    EXPECT_TRUE(check(kBox, h, conservative).ok());
    EXPECT_TRUE(check(kBox, h, fast).ok());
    EXPECT_TRUE(check(kFarBox, answer(Verdict::miss), certified).ok());
}

TEST(ContractCheck, CertifiedRejectsATNotFaithful) {
    // Two ulps below 1/3: not one of the two doubles enclosing it.
    const auto c = check(kBox, hit(step_down(third_lo()), two_thirds_hi(), 0), certified);
    EXPECT_TRUE(c.has(Breach::not_exact));
    EXPECT_TRUE(c.promise_broken());
    EXPECT_EQ(c.first(), Breach::not_exact);
    EXPECT_EQ(c.judgement.enter_ulps, 1u);
    // t_exit one step beyond its upper rounding.
    EXPECT_TRUE(check(kBox, hit(third_lo(), step_up(two_thirds_hi()), 0), certified).has(Breach::not_exact));
}

TEST(ContractCheck, CertifiedRejectsAWrongFaceConservativeAndFastDoNot) {
    const auto h = hit(third_lo(), two_thirds_hi(), 1);  // +x side instead of -x
    const auto c = check(kBox, h, certified);
    EXPECT_TRUE(c.has(Breach::not_exact));
    EXPECT_EQ(c.judgement.outcome, oracle::Outcome::face_mismatch);
    EXPECT_EQ(c.mode_judgement().outcome, oracle::Outcome::face_mismatch);

    const auto k = check(kBox, h, conservative);
    EXPECT_TRUE(k.ok());
    EXPECT_EQ(k.judgement.outcome, oracle::Outcome::face_mismatch);  // counted by a tally
    EXPECT_EQ(k.mode_judgement().outcome, oracle::Outcome::agree);   // but not the mode's business
    EXPECT_TRUE(check(kBox, h, fast).ok());
}

TEST(ContractCheck, CertifiedRejectsAWrongVerdict) {
    EXPECT_TRUE(check(kBox, answer(Verdict::miss), certified).has(Breach::not_exact));
    EXPECT_TRUE(check(kFarBox, hit(0, 1, 0), certified).has(Breach::not_exact));
}

TEST(ContractCheck, ConservativeRejectsAFalseMissButNotAFalseHit) {
    const auto c = check(kBox, answer(Verdict::miss), conservative);
    EXPECT_TRUE(c.has(Breach::false_miss));
    EXPECT_TRUE(c.promise_broken());
    EXPECT_EQ(c.first(), Breach::false_miss);
    EXPECT_TRUE(check(kFarBox, hit(0, 1, 0), conservative).ok());  // a false hit is allowed
    EXPECT_TRUE(check(kBox, answer(Verdict::miss), fast).ok());     // fast promises nothing
}

TEST(ContractCheck, ConservativeRejectsAnIntervalThatDoesNotEnclose) {
    // Entering at the upper rounding of 1/3 starts after the exact entry.
    const auto c = check(kBox, hit(third_hi(), two_thirds_hi(), 0), conservative);
    EXPECT_TRUE(c.has(Breach::not_enclosing));
    EXPECT_EQ(c.first(), Breach::not_enclosing);
    EXPECT_TRUE(check(kBox, hit(third_lo(), two_thirds_lo(), 0), conservative).has(Breach::not_enclosing));
    // Wider than the exact interval is fine, and a certified answer may round inward.
    EXPECT_TRUE(check(kBox, hit(0.25, 0.75, 0), conservative).ok());
    EXPECT_TRUE(check(kBox, hit(third_hi(), two_thirds_lo(), 0), certified).ok());
}

TEST(ContractCheck, EveryModeRejectsAValidityMismatch) {
    const Aabb<double> inverted{{1, 0, 0}, {0, 1, 1}};  // lo > hi: invalid
    for (const ModeId m : {ModeId::fast, ModeId::conservative, ModeId::certified}) {
        const auto e = oracle::exact(kRay, inverted);
        const auto c = oracle::check_contract(m, true, kRay, answer(Verdict::miss), e);
        EXPECT_TRUE(c.has(Breach::invalid_not_reported)) << oracle::to_string(m);
        EXPECT_TRUE(c.promise_broken()) << oracle::to_string(m);
        EXPECT_TRUE(c.invalid_mismatch()) << oracle::to_string(m);
        EXPECT_EQ(c.first(), Breach::invalid_not_reported) << oracle::to_string(m);
        EXPECT_TRUE(oracle::check_contract(m, true, kRay, answer(Verdict::invalid), e).ok()) << oracle::to_string(m);

        const auto v = oracle::check_contract(m, true, kRay, answer(Verdict::invalid), oracle::exact(kRay, kBox));
        EXPECT_TRUE(v.has(Breach::valid_reported_invalid)) << oracle::to_string(m);
        EXPECT_EQ(v.first(), Breach::valid_reported_invalid) << oracle::to_string(m);
    }
}

TEST(ContractCheck, EveryModeRejectsANaNInAHitAndAVerdictOutOfRange) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (const ModeId m : {ModeId::fast, ModeId::conservative, ModeId::certified}) {
        const auto e = oracle::exact(kRay, kBox);
        const auto c = oracle::check_contract(m, true, kRay, hit(third_lo(), nan, 0), e);
        EXPECT_TRUE(c.has(Breach::nan_in_hit)) << oracle::to_string(m);
        EXPECT_EQ(c.first(), Breach::nan_in_hit) << oracle::to_string(m);

        Hit<double> odd = hit(third_lo(), two_thirds_hi(), 0);
        odd.verdict = static_cast<Verdict>(7);
        const auto o = oracle::check_contract(m, true, kRay, odd, e);
        EXPECT_TRUE(o.has(Breach::verdict_out_of_range)) << oracle::to_string(m);
        EXPECT_EQ(o.first(), Breach::verdict_out_of_range) << oracle::to_string(m);
    }
}

TEST(ContractCheck, ConservativeAndCertifiedRejectAnIntervalOutsideTheRange) {
    // Ray range [0, 1/2]: the exact interval is [1/3, 1/2].
    Ray<double> r = kRay;
    r.t_max = 0.5;
    const auto e = oracle::exact(r, kBox);
    const auto beyond = hit(0.25, 0.625, 0);  // encloses [1/3, 1/2] but ends after t_max
    const auto c = oracle::check_contract(r, kBox, beyond, e, conservative);
    EXPECT_TRUE(c.has(Breach::interval_out_of_range));
    EXPECT_FALSE(c.promise_broken());  // a breach of the answer's form, not of the promise
    EXPECT_EQ(c.first(), Breach::interval_out_of_range);
    EXPECT_TRUE(oracle::check_contract(r, kBox, hit(0.5, 0.25, 0), e, certified).has(Breach::interval_out_of_range));
    EXPECT_TRUE(oracle::check_contract(r, kBox, beyond, e, fast).ok());
}

TEST(ContractCheck, FacesOutOfRangeAreRejectedPerShape) {
    const auto box_face = check(kBox, hit(0.25, 0.75, 6), conservative);
    EXPECT_TRUE(box_face.has(Breach::face_out_of_range));
    EXPECT_EQ(box_face.first(), Breach::face_out_of_range);
    EXPECT_TRUE(check(kBox, hit(0.25, 0.75, -2), conservative).has(Breach::face_out_of_range));

    // The ball of radius 1/2 about (1/2, 1/2, 1/2): [1/3, 2/3] on this ray, as for the box.
    const Sphere<double> ball{{0.5, 0.5, 0.5}, 0.5};
    const auto s = check(ball, hit(0.25, 0.75, 0), conservative);
    EXPECT_TRUE(s.has(Breach::face_not_none));
    EXPECT_EQ(s.first(), Breach::face_not_none);
    EXPECT_TRUE(check(ball, hit(0.25, 0.75, -1), conservative).ok());
    EXPECT_TRUE(check(ball, hit(0.25, 0.75, 0), fast).ok());
}

TEST(ContractCheck, BreachesAreNamedAsTheFuzzTargetsReportThem) {
    EXPECT_STREQ(oracle::describe(Breach::not_exact), "certified answer not exact");
    EXPECT_STREQ(oracle::describe(Breach::false_miss), "conservative missed an exact hit");
    EXPECT_STREQ(oracle::describe(Breach::invalid_not_reported), "invalid input not reported");
    for (unsigned k = 0; k < oracle::kBreachCount; ++k) EXPECT_STRNE(oracle::describe(Breach(1u << k)), "?");
}

TEST(ContractCheck, TheKernelsAnswersPass) {
    EXPECT_TRUE(check(kBox, intersect(kRay, kBox, certified), certified).ok());
    EXPECT_TRUE(check(kBox, intersect(kRay, kBox, conservative), conservative).ok());
    EXPECT_TRUE(check(kFarBox, intersect(kRay, kFarBox, certified), certified).ok());
}

TEST(Tally, CountsOutcomesAndTErrors) {
    oracle::Tally t;
    const auto e = oracle::exact(kRay, kBox);
    const auto ok = oracle::judge(hit(third_lo(), two_thirds_hi(), 0), e);
    const auto off = oracle::judge(hit(step_down(third_lo()), two_thirds_hi(), 1), e);
    const auto miss = oracle::judge(answer(Verdict::miss), e);
    for (const auto& j : {ok, off, miss}) {
        ++t.cases;
        t.count_outcome(j);
    }
    t.count_interval(ok);
    t.count_interval(off);
    t.count_t(3);
    t.count_coherence(hit(1, 0, 0));
    t.count_coherence(hit(0, 1, 0));
    EXPECT_EQ(t.cases, 3u);
    EXPECT_EQ(t.false_miss, 1u);
    EXPECT_EQ(t.face_mismatch, 1u);
    EXPECT_EQ(t.wrong(), 1u);
    EXPECT_EQ(t.t_judged, 3u);
    EXPECT_EQ(t.t_off, 2u);
    EXPECT_EQ(t.max_ulps, 3u);
    EXPECT_EQ(t.not_enclosing, 0u);  // an earlier entry still encloses
    EXPECT_EQ(t.incoherent, 1u);
}

}  // namespace
