#include "sf/knowledge/store.hpp"

#include <gtest/gtest.h>

#include "sf/knowledge/vocab.hpp"

namespace sf::knowledge {
namespace {

struct StoreTest : ::testing::Test {
  Dictionary d;
  TripleStore st{d};
  TermId iri(std::string_view local) { return d.iri("http://ex/" + std::string(local)); }
  std::vector<TripleId> all(ValuePattern p, TripleId limit = kNoTriple) {
    std::vector<TripleId> out;
    st.match(p, limit, [&](TripleId id) { out.push_back(id); });
    return out;
  }
};

TEST_F(StoreTest, InsertDeduplicatesByValue) {
  const Triple t{iri("a"), iri("p"), d.literal("1", vocab::kXsdInt)};
  auto [id, added] = st.insert(t);
  EXPECT_TRUE(added);
  auto [again, added_again] = st.insert(Triple{iri("a"), iri("p"), d.literal("1.0", vocab::kXsdDecimal)});
  EXPECT_FALSE(added_again);
  EXPECT_EQ(again, id);
  EXPECT_EQ(st.size(), 1U);
  EXPECT_EQ(st.find(t), id);
}

TEST_F(StoreTest, MatchUsesEveryIndexAndKeepsIdOrder) {
  const TermId a = iri("a"), b = iri("b"), p = iri("p"), q = iri("q");
  const TripleId t0 = st.insert({a, p, b}).first;
  const TripleId t1 = st.insert({b, p, a}).first;
  const TripleId t2 = st.insert({a, q, b}).first;
  const TripleId t3 = st.insert({a, p, a}).first;
  EXPECT_EQ(all({a, p, kNoTerm}), (std::vector<TripleId>{t0, t3}));
  EXPECT_EQ(all({kNoTerm, p, a}), (std::vector<TripleId>{t1, t3}));
  EXPECT_EQ(all({kNoTerm, p, kNoTerm}), (std::vector<TripleId>{t0, t1, t3}));
  EXPECT_EQ(all({a, kNoTerm, kNoTerm}), (std::vector<TripleId>{t0, t2, t3}));
  EXPECT_EQ(all({kNoTerm, kNoTerm, b}), (std::vector<TripleId>{t0, t2}));
  EXPECT_EQ(all({a, kNoTerm, b}), (std::vector<TripleId>{t0, t2}));
  EXPECT_EQ(all({a, p, b}), (std::vector<TripleId>{t0}));
  EXPECT_EQ(all({}), (std::vector<TripleId>{t0, t1, t2, t3}));
  EXPECT_EQ(all({kNoTerm, p, kNoTerm}, t3), (std::vector<TripleId>{t0, t1}));  // older than t3 only
  EXPECT_TRUE(st.contains({kNoTerm, q, kNoTerm}));
  EXPECT_FALSE(st.contains({b, q, kNoTerm}));
}

TEST_F(StoreTest, ObjectsMatchByValue) {
  const TermId m = iri("m"), temp = iri("temperature");
  const TripleId id = st.insert({m, temp, d.literal("20", vocab::kXsdInt)}).first;
  EXPECT_EQ(all({m, temp, d.value_id(d.literal("20.0", vocab::kXsdDecimal))}), std::vector<TripleId>{id});
  EXPECT_TRUE(all({m, temp, d.value_id(d.literal("20.0", vocab::kXsdDouble))}).empty());
}

TEST_F(StoreTest, EraseHidesAndCompactionKeepsTheRest) {
  std::vector<TripleId> ids;
  for (int i = 0; i < 10000; ++i) {
    ids.push_back(
        st.insert({iri("s" + std::to_string(i % 100)), iri("p"), d.literal(std::to_string(i))}).first);
  }
  for (int i = 0; i < 10000; i += 2) {
    st.erase(ids[static_cast<std::size_t>(i)]);
  }
  EXPECT_EQ(st.size(), 5000U);
  st.compact_if_worthwhile();
  EXPECT_EQ(all({iri("s1"), iri("p"), kNoTerm}).size(), 100U);  // odd i: kept
  EXPECT_TRUE(all({iri("s2"), iri("p"), kNoTerm}).empty());     // even i: erased
  EXPECT_EQ(all({kNoTerm, iri("p"), kNoTerm}).size(), 5000U);
  EXPECT_EQ(st.find({iri("s0"), iri("p"), d.literal("0")}), kNoTriple);
  const auto [again, added] = st.insert({iri("s0"), iri("p"), d.literal("0")});
  EXPECT_TRUE(added);
  EXPECT_GT(again, ids.back());
}

}  // namespace
}  // namespace sf::knowledge
