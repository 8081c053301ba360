"""Models as feature sets, the model difference Delta, and updated models ``human + E``.

``Gamma(M)`` turns every condition of a model into one named feature (docs/models.md).
Action-schema features are lifted: one feature covers every grounding.  The model difference
``Delta`` is the symmetric difference of the two feature sets, except that a schema cost (or a
cost-function value) the two models disagree on is *one* feature whose application sets the
human's value to the robot's.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

from mega_sat.model.lifted import Atom, CostTerm, Model, Schema, atom_str

# Feature kinds, in the order they are listed in output.
INIT, GOAL, NEGGOAL, SCHEMA, PRE, NEGPRE, ADD, DEL, COST, FVALUE = (
    "init",
    "goal",
    "neggoal",
    "schema",
    "pre",
    "negpre",
    "add",
    "del",
    "cost",
    "fvalue",
)
KIND_ORDER = {
    k: i for i, k in enumerate((INIT, GOAL, NEGGOAL, SCHEMA, PRE, NEGPRE, ADD, DEL, COST, FVALUE))
}


def cost_str(cost: int | CostTerm) -> str:
    return str(cost) if isinstance(cost, int) else "(" + " ".join(cost) + ")"


@dataclass(frozen=True)
class Feature:
    """One condition of a model.

    ``action`` is the schema name ('' for initial-state, goal and function-value features).
    ``atom`` is the (lifted or ground) atom; for ``schema`` it holds the parameter list, for
    ``cost`` the cost (``(value,)`` or the cost term), for ``fvalue`` the ground function term
    followed by its value as a string.  ``signature`` (``schema`` only) holds the parameters'
    types for the printed name; it is not part of the feature's identity, so two models whose
    schema types a parameter differently still share the schema's existence feature (the type
    difference is a precondition feature of its own).
    """

    kind: str
    action: str
    atom: tuple[str, ...]
    signature: tuple[str, ...] = field(default=(), compare=False)

    @property
    def name(self) -> str:
        """Canonical name, in the paper's style (``has-initial-state-clear_path p1 p8``)."""
        k, a = self.kind, self.action
        if k == INIT:
            return f"has-initial-state-{atom_str(self.atom)}"
        if k == GOAL:
            return f"has-goal-state-{atom_str(self.atom)}"
        if k == NEGGOAL:
            return f"has-negative-goal-state-{atom_str(self.atom)}"
        if k == SCHEMA:
            params = [
                f"{p} - {t}" if t else p
                for p, t in zip(self.atom, self.signature or ("",) * len(self.atom), strict=True)
            ]
            return f"{a}-has-parameters-{' '.join(params)}".rstrip("-")
        if k == PRE:
            return f"{a}-has-precondition-{atom_str(self.atom)}"
        if k == NEGPRE:
            return f"{a}-has-negprecondition-{atom_str(self.atom)}"
        if k == ADD:
            return f"{a}-has-add-effect-{atom_str(self.atom)}"
        if k == DEL:
            return f"{a}-has-delete-effect-{atom_str(self.atom)}"
        if k == COST:
            return f"{a}-has-cost-{self.atom[0]}"
        if k == FVALUE:
            return f"has-initial-value-{atom_str(self.atom[:-1])}={self.atom[-1]}"
        raise ValueError(f"unknown feature kind {k!r}")

    def __str__(self) -> str:
        return self.name


@dataclass(frozen=True)
class Update:
    """One element of Delta: a feature and whether the robot model has it.

    Applying it to a human model adds the feature when ``robot_has`` is true and removes it
    otherwise.  Cost and function-value updates always have ``robot_has`` true: they *set* the
    human's value to the robot's.
    """

    feature: Feature
    robot_has: bool

    @property
    def name(self) -> str:
        return ("add-" if self.robot_has else "remove-") + self.feature.name

    def __str__(self) -> str:
        return self.name


def schema_features(s: Schema) -> set[Feature]:
    """The features of one schema (existence, components, cost)."""
    out = {Feature(SCHEMA, s.name, s.params, s.param_types())}
    for kind, atoms in ((PRE, s.pre), (NEGPRE, s.negpre), (ADD, s.add), (DEL, s.delete)):
        out.update(Feature(kind, s.name, a) for a in atoms)
    out.add(Feature(COST, s.name, (cost_str(s.cost),)))
    return out


def gamma(model: Model) -> frozenset[Feature]:
    """``Gamma(M)``: every condition of ``model`` as a feature."""
    out: set[Feature] = set()
    out.update(Feature(INIT, "", a) for a in model.init)
    out.update(Feature(GOAL, "", a) for a in model.goal)
    out.update(Feature(NEGGOAL, "", a) for a in model.neggoal)
    for s in model.schemas.values():
        out.update(schema_features(s))
    out.update(Feature(FVALUE, "", term + (str(v),)) for term, v in model.functions.items())
    return frozenset(out)


def _in_own_signature(f: Feature, owner: Model, other: Model) -> bool:
    """True for a type precondition of a schema only ``owner`` has: it travels with the
    schema's existence update (its signature), so it is no update of its own."""
    s = owner.schemas.get(f.action)
    return (
        f.kind == PRE and s is not None and f.action not in other.schemas and f.atom in s.signature
    )


def model_difference(robot: Model, human: Model) -> tuple[Update, ...]:
    """``Delta``: the updates that turn ``human`` into ``robot``, in canonical order.

    ``human`` must already use the robot's parameter names for shared schemas (see
    :func:`mega_sat.model.task.align_human`).
    """
    gr, gh = gamma(robot), gamma(human)
    ups: list[Update] = []
    for f in gr - gh:
        if f.kind == COST and f.action not in human.schemas:
            continue  # a schema only the robot has keeps its own cost: no cost feature
        if _in_own_signature(f, robot, human):
            continue
        ups.append(Update(f, True))
    for f in gh - gr:
        if f.kind in (COST, FVALUE):
            continue  # replaced by the robot's value (added above), or a human-only schema's own
        if _in_own_signature(f, human, robot):
            continue

        ups.append(Update(f, False))
    # kind, then additions before removals (the paper prints adds first), then name
    ups.sort(
        key=lambda u: (
            KIND_ORDER[u.feature.kind],
            not u.robot_has,
            u.feature.action,
            u.feature.atom,
        )
    )
    return tuple(ups)


def apply_updates(human: Model, robot: Model, updates: Iterable[Update]) -> Model:
    """``human + E``: the human model with every update of ``E`` applied.

    Every subset of Delta gives a well-defined model: a schema whose existence feature is
    added starts with its signature (the parameter types) and only the other components ``E``
    adds; a schema removed takes its components with it.  Cost of a schema present in only one
    model is that model's cost.
    """
    feats = set(gamma(human))
    for u in updates:
        f = u.feature
        if f.kind == COST:
            feats = {g for g in feats if not (g.kind == COST and g.action == f.action)}
            feats.add(f)
        elif f.kind == FVALUE:
            term = f.atom[:-1]
            feats = {g for g in feats if not (g.kind == FVALUE and g.atom[:-1] == term)}
            feats.add(f)
        elif u.robot_has:
            feats.add(f)
            if f.kind == SCHEMA and f.action not in human.schemas:
                feats.update(Feature(PRE, f.action, a) for a in robot.schemas[f.action].signature)
        else:
            feats.discard(f)
    return model_from_features(feats, human, robot)


def _parse_cost(text: str) -> int | CostTerm:
    if text.startswith("("):
        return tuple(text[1:-1].split())
    return int(text)


def model_from_features(feats: Iterable[Feature], human: Model, robot: Model) -> Model:
    """Rebuild a :class:`Model` from a feature set of the ``human``/``robot`` family."""
    feats = set(feats)
    schema_params = {f.action: f.atom for f in feats if f.kind == SCHEMA}
    parts: dict[str, dict[str, set[Atom]]] = {
        a: {PRE: set(), NEGPRE: set(), ADD: set(), DEL: set()} for a in schema_params
    }
    costs: dict[str, int | CostTerm] = {}
    for f in feats:
        if f.action in parts and f.kind in (PRE, NEGPRE, ADD, DEL):
            parts[f.action][f.kind].add(f.atom)
        elif f.kind == COST:
            costs[f.action] = _parse_cost(f.atom[0])
    schemas = {}
    for a, params in sorted(schema_params.items()):
        src = human.schemas.get(a) or robot.schemas[a]
        cost = costs.get(a, src.cost)  # a schema only one model has: that model's cost
        p = parts[a]
        schemas[a] = Schema(
            a,
            params,
            frozenset(p[PRE]),
            frozenset(p[NEGPRE]),
            frozenset(p[ADD]),
            frozenset(p[DEL]),
            cost,
            src.signature & frozenset(p[PRE]),
        )
    functions = {f.atom[:-1]: int(f.atom[-1]) for f in feats if f.kind == FVALUE}
    predicates = dict(robot.predicates)
    predicates.update(human.predicates)
    farities = dict(robot.function_arities)
    farities.update(human.function_arities)
    return Model(
        domain_name=human.domain_name,
        problem_name=human.problem_name,
        predicates=predicates,
        schemas=schemas,
        objects=human.objects | robot.objects,
        init=frozenset(f.atom for f in feats if f.kind == INIT),
        goal=frozenset(f.atom for f in feats if f.kind == GOAL),
        neggoal=frozenset(f.atom for f in feats if f.kind == NEGGOAL),
        type_predicates=human.type_predicates | robot.type_predicates,
        functions=functions,
        function_arities=farities,
        uses_costs=human.uses_costs or robot.uses_costs,
    )
