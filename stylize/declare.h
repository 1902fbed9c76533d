// stylize/declare.h — a registry entry from its declaration, its typed parameter table and one
// typed run function (docs/stylize.md "Writing a stage"): the entry's parameter list is the
// table's, and a compiled pipeline binds the parameter values to the typed struct once
// (StageVariant::bind), not on every run.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "stylize/stage.h"

namespace aq::stylize {

//! The entry declared by `v` (names, doc, ports, reference, in place, row windows, scene inputs),
//! with parameters `table` and the run `fn(StageIO&, const P&, const Exec&)`: v.params is the
//! table's; v.run and v.bind call fn with the values as P — bind converts them once, when a
//! pipeline compiles the step (CompiledStep::step). Registry::add puts the ports' check (check_io)
//! before both.
template <class P, class Fn>
StageVariant declare(StageVariant v, ParamTable<P> table, Fn fn) {
    auto t = std::make_shared<const ParamTable<P>>(std::move(table));
    v.params = t->descs();
    v.run = [t, fn](StageIO& io, const ParamValues& pv, const Exec& ex) { fn(io, t->from(pv), ex); };
    v.bind = [t, fn](const ParamValues& pv) -> StepFn {
        return [p = t->from(pv), fn](StageIO& io, const Exec& ex) { fn(io, p, ex); };
    };
    return v;
}

//! declare, with the cross-field rules `check(const P&)` (throws aq::Error) as StageVariant::validate.
template <class P, class Fn, class Check>
StageVariant declare(StageVariant v, ParamTable<P> table, Fn fn, Check check) {
    auto t = std::make_shared<const ParamTable<P>>(table);
    v.validate = [t, check](const ParamValues& pv) { check(t->from(pv)); };
    return declare(std::move(v), std::move(table), std::move(fn));
}

//! The parameters of a variant that has none.
struct NoParams {};

}  // namespace aq::stylize
