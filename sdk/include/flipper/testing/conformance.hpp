#pragma once
/// @file conformance.hpp
/// Umbrella for the conformance kit: the loader layer (on a built .so) plus the per-kind
/// behaviour kits (on an instance). Include the single kit you need to keep test builds fast.
#include "flipper/testing/loader.hpp"
#include "flipper/testing/parser_conformance.hpp"
#include "flipper/testing/planner_conformance.hpp"
#include "flipper/testing/rewriter_conformance.hpp"
#include "flipper/testing/scorer_conformance.hpp"
#include "flipper/testing/similarity_conformance.hpp"
#include "flipper/testing/world_conformance.hpp"
