// The plugin ABI's pinned values (docs/sdk-migration.md "What the ABI number covers"): every
// enumerator that crosses the kernel/plugin boundary, the descriptor's layout and the inline
// namespace's tie to FLIPPER_PLUGIN_ABI, checked at compile time. A failure here means an edit
// changed what built plugins rely on: put the value back, or bump FLIPPER_PLUGIN_ABI (and the
// SDK major) and write the change into docs/sdk-migration.md.
#include <cstddef>
#include <type_traits>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/grammar.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/plugin.hpp"
#include "flipper/sdk/stop.hpp"
#include "flipper/sdk/version.hpp"

namespace flipper::sdk {
namespace {

#define FLIPPER_PIN(enumerator, value)                         \
  static_assert(static_cast<long long>(enumerator) == (value), \
                #enumerator " must be " #value " (the plugin ABI)")

// The namespace is abi<N>, N the ABI number (version.hpp).
static_assert(FLIPPER_ABI_NAMESPACE::kPluginAbi == FLIPPER_PLUGIN_ABI);
static_assert(std::is_same_v<SdkVersion, abi3::SdkVersion>,
              "the inline namespace is not abi3: rename it here with the ABI bump");

// Underlying types: a node's kind and sort are bytes.
static_assert(std::is_same_v<std::underlying_type_t<Sort>, std::uint8_t>);
static_assert(std::is_same_v<std::underlying_type_t<Kind>, std::uint8_t>);
static_assert(std::is_same_v<std::underlying_type_t<Symbol::Type>, std::uint8_t>);
static_assert(std::is_same_v<std::underlying_type_t<RuleOrigin>, std::uint8_t>);
static_assert(std::is_same_v<std::underlying_type_t<PlanStatus>, int>);
static_assert(std::is_same_v<std::underlying_type_t<TraceStep::Act>, int>);
static_assert(std::is_same_v<std::underlying_type_t<StopCause>, int>);
static_assert(std::is_same_v<std::underlying_type_t<PluginKind>, std::uint32_t>);

FLIPPER_PIN(PluginKind::world, 1);
FLIPPER_PIN(PluginKind::planner, 2);
FLIPPER_PIN(PluginKind::parser, 3);
FLIPPER_PIN(PluginKind::scorer, 4);
FLIPPER_PIN(PluginKind::rewriter, 5);
FLIPPER_PIN(PluginKind::similarity, 6);
FLIPPER_PIN(PluginKind::frontend, 7);

FLIPPER_PIN(Sort::Action, 0);
FLIPPER_PIN(Sort::Condition, 1);
FLIPPER_PIN(Sort::Point, 2);
FLIPPER_PIN(Sort::Area, 3);
FLIPPER_PIN(Sort::Collection, 4);
FLIPPER_PIN(Sort::Item, 5);
FLIPPER_PIN(Sort::CountedItem, 6);
FLIPPER_PIN(Sort::Filter, 7);
FLIPPER_PIN(Sort::Number, 8);
FLIPPER_PIN(Sort::Direction, 9);
FLIPPER_PIN(Sort::Color, 10);
FLIPPER_PIN(Sort::Shape, 11);
FLIPPER_PIN(Sort::ItemAct, 12);
FLIPPER_PIN(Sort::Property, 13);

FLIPPER_PIN(Kind::Seq, 0);
FLIPPER_PIN(Kind::Strict, 1);
FLIPPER_PIN(Kind::Move, 2);
FLIPPER_PIN(Kind::VisitPoint, 3);
FLIPPER_PIN(Kind::VisitArea, 4);
FLIPPER_PIN(Kind::VisitCollection, 5);
FLIPPER_PIN(Kind::Pick, 6);
FLIPPER_PIN(Kind::Drop, 7);
FLIPPER_PIN(Kind::ForeachPoint, 8);
FLIPPER_PIN(Kind::ForeachArea, 9);
FLIPPER_PIN(Kind::Repeat, 10);
FLIPPER_PIN(Kind::If, 11);
FLIPPER_PIN(Kind::While, 12);
FLIPPER_PIN(Kind::CondAnd, 13);
FLIPPER_PIN(Kind::CondOr, 14);
FLIPPER_PIN(Kind::CondNot, 15);
FLIPPER_PIN(Kind::ItemAtPoint, 16);
FLIPPER_PIN(Kind::ItemAtArea, 17);
FLIPPER_PIN(Kind::RobotHas, 18);
FLIPPER_PIN(Kind::RobotAtPoint, 19);
FLIPPER_PIN(Kind::RobotAtArea, 20);
FLIPPER_PIN(Kind::Possible, 21);
FLIPPER_PIN(Kind::PointXY, 22);
FLIPPER_PIN(Kind::Current, 23);
FLIPPER_PIN(Kind::PointVar, 24);
FLIPPER_PIN(Kind::World, 25);
FLIPPER_PIN(Kind::Room, 26);
FLIPPER_PIN(Kind::AreaVar, 27);
FLIPPER_PIN(Kind::PointList, 28);
FLIPPER_PIN(Kind::Corners, 29);
FLIPPER_PIN(Kind::AreaOr, 30);
FLIPPER_PIN(Kind::AreaAnd, 31);
FLIPPER_PIN(Kind::AreaMinus, 32);
FLIPPER_PIN(Kind::AreaContaining, 33);
FLIPPER_PIN(Kind::Rooms, 34);
FLIPPER_PIN(Kind::AreaList, 35);
FLIPPER_PIN(Kind::CollOr, 36);
FLIPPER_PIN(Kind::CollAnd, 37);
FLIPPER_PIN(Kind::CollMinus, 38);
FLIPPER_PIN(Kind::CollContaining, 39);
FLIPPER_PIN(Kind::Item, 40);
FLIPPER_PIN(Kind::Every, 41);
FLIPPER_PIN(Kind::FilterIs, 42);
FLIPPER_PIN(Kind::FilterAnd, 43);
FLIPPER_PIN(Kind::FilterOr, 44);
FLIPPER_PIN(Kind::FilterNot, 45);
FLIPPER_PIN(Kind::Num, 46);
FLIPPER_PIN(Kind::Add, 47);
FLIPPER_PIN(Kind::Sub, 48);
FLIPPER_PIN(Kind::Direction, 49);
FLIPPER_PIN(Kind::Color, 50);
FLIPPER_PIN(Kind::Shape, 51);
FLIPPER_PIN(Kind::ItemAct, 52);
FLIPPER_PIN(Kind::ItemAction, 53);
FLIPPER_PIN(Kind::Hole, 54);

FLIPPER_PIN(Symbol::Type::token, 0);
FLIPPER_PIN(Symbol::Type::category, 1);
FLIPPER_PIN(Symbol::Type::number, 2);
FLIPPER_PIN(Symbol::Type::color, 3);
FLIPPER_PIN(Symbol::Type::shape, 4);
FLIPPER_PIN(Symbol::Type::direction, 5);

FLIPPER_PIN(RuleOrigin::core, 0);
FLIPPER_PIN(RuleOrigin::simple, 1);
FLIPPER_PIN(RuleOrigin::best, 2);
FLIPPER_PIN(RuleOrigin::alignment, 3);
FLIPPER_PIN(RuleOrigin::rewriting, 4);

FLIPPER_PIN(PlanStatus::found, 0);
FLIPPER_PIN(PlanStatus::no_path, 1);
FLIPPER_PIN(PlanStatus::stopped, 2);
FLIPPER_PIN(PlanStatus::invalid, 3);

FLIPPER_PIN(TraceStep::Act::move, 0);
FLIPPER_PIN(TraceStep::Act::pick, 1);
FLIPPER_PIN(TraceStep::Act::drop, 2);

FLIPPER_PIN(StopCause::none, 0);
FLIPPER_PIN(StopCause::cancelled, 1);
FLIPPER_PIN(StopCause::cpu_budget, 2);
FLIPPER_PIN(StopCause::wall_backstop, 3);

#undef FLIPPER_PIN

// The handshake and the descriptor (plugin.hpp): C layout, checked by the handshake at load
// time; pinned here on LP64 so that a changed field is caught when it is made.
static_assert(std::is_standard_layout_v<FlipperPluginDescriptor>);
static_assert(sizeof(FlipperHandshake) == 12);
#if __SIZEOF_POINTER__ == 8
static_assert(offsetof(FlipperPluginDescriptor, kind) == 12);
static_assert(offsetof(FlipperPluginDescriptor, name) == 16);
static_assert(offsetof(FlipperPluginDescriptor, fingerprint) == 40);
static_assert(offsetof(FlipperPluginDescriptor, describe) == 48);
static_assert(offsetof(FlipperPluginDescriptor, create) == 56);
static_assert(offsetof(FlipperPluginDescriptor, destroy) == 64);
static_assert(offsetof(FlipperPluginDescriptor, reserved) == 72);
static_assert(sizeof(FlipperPluginDescriptor) == 104);
#endif

}  // namespace
}  // namespace flipper::sdk
