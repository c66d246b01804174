#pragma once
/// @file sdk.hpp
/// Everything a plugin author needs, in one include.
#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/derivation.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/geometry.hpp"
#include "flipper/sdk/grammar.hpp"
#include "flipper/sdk/params.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/plugin.hpp"
#include "flipper/sdk/rewriter.hpp"
#include "flipper/sdk/scorer.hpp"
#include "flipper/sdk/similarity.hpp"
#include "flipper/sdk/version.hpp"
#include "flipper/sdk/world.hpp"
