"""Write a :class:`~mega_sat.model.lifted.Model` as untyped PDDL that Fast Downward and VAL accept.

This is how an updated human model ``human + E`` becomes checkable by external tools and
readable by a user.  The output is untyped: type predicates are ordinary predicates and their
atoms are ordinary initial-state atoms, exactly as the model holds them, so reading the files
back gives the same features.  Output is sorted, so equal models give byte-identical files.

Costs are written (``:action-costs``, ``(increase (total-cost) ...)``, the metric) when the
model declares them, has cost functions, or any schema costs other than 1, so no cost is lost.
"""

from __future__ import annotations

from pathlib import Path

from mega_sat.model.lifted import (
    EQUALITY,
    Atom,
    CostTerm,
    Model,
    Schema,
    atom_pddl,
    rename_schema,
    tests_equality,
)


def _writes_costs(model: Model) -> bool:
    return (
        model.uses_costs
        or bool(model.functions or model.function_arities)
        or any(s.cost != 1 for s in model.schemas.values())
    )


def _schema_atoms(s: Schema) -> list[Atom]:
    return [*s.pre, *s.negpre, *s.add, *s.delete]


def _arities(pairs: list[tuple[str, int]], what: str) -> dict[str, int]:
    out: dict[str, int] = {}
    for name, n in pairs:
        if out.setdefault(name, n) != n:
            raise ValueError(f"{what} '{name}' is used with {out[name]} and {n} arguments")
    return out


def _predicate_arities(model: Model) -> dict[str, int]:
    """Declared arities plus those of any atom the model uses (hand-built models); equality
    is built into PDDL and not declared."""
    atoms = [*model.init, *model.goal, *model.neggoal]
    for s in model.schemas.values():
        atoms.extend(_schema_atoms(s))
    out = _arities([*model.predicates.items(), *((a[0], len(a) - 1) for a in atoms)], "predicate")
    out.pop(EQUALITY, None)
    return out


def _equality_atoms(model: Model, objects: list[str]) -> list[Atom]:
    """The model's ``(= a b)`` atoms, which PDDL's equality gives for free; an ``(= a b)``
    other than the identity over the written objects cannot be written and is an error."""
    atoms = sorted(a for a in model.init if a[0] == EQUALITY)
    if any(a[0] == EQUALITY for s in model.schemas.values() for a in (*s.add, *s.delete)) or (
        tests_equality(model.schemas.values())
        and atoms != [(EQUALITY, o, o) for o in sorted(objects)]
    ):
        raise ValueError("the model's '=' atoms are not PDDL's equality over its objects")
    return atoms


def _function_arities(model: Model) -> dict[str, int]:
    terms: list[CostTerm] = list(model.functions)
    terms += [s.cost for s in model.schemas.values() if not isinstance(s.cost, int)]
    return _arities(
        [*model.function_arities.items(), *((t[0], len(t) - 1) for t in terms)], "function"
    )


def _constants(model: Model) -> list[str]:
    """Objects named inside schemas: PDDL needs them declared in the domain."""
    out: set[str] = set()
    for s in model.schemas.values():
        terms = _schema_atoms(s)
        if not isinstance(s.cost, int):
            terms.append(s.cost)
        out.update(x for t in terms for x in t[1:] if not x.startswith("?"))
    return sorted(out)


def _vars(n: int) -> str:
    return " ".join(f"?x{i}" for i in range(n))


def _conj(parts: list[str], indent: str) -> str:
    if not parts:
        return "(and)"
    return "(and " + f"\n{indent}     ".join(parts) + ")"


def _action(s: Schema, costs: bool) -> str:
    pre = [atom_pddl(a) for a in sorted(s.pre)]
    pre += [f"(not {atom_pddl(a)})" for a in sorted(s.negpre)]
    eff = [atom_pddl(a) for a in sorted(s.add)]
    eff += [f"(not {atom_pddl(a)})" for a in sorted(s.delete)]
    if costs:
        value = str(s.cost) if isinstance(s.cost, int) else atom_pddl(s.cost)
        eff.append(f"(increase (total-cost) {value})")
    ind = " " * 18
    return (
        f"  (:action {s.name}\n"
        f"    :parameters ({' '.join(s.params)})\n"
        f"    :precondition {_conj(pre, ind)}\n"
        f"    :effect {_conj(eff, ind[:12])})"
    )


def domain_to_pddl(model: Model, *, plain_variables: bool = False) -> str:
    """The domain file of ``model`` (untyped; type predicates are ordinary predicates).

    ``plain_variables``: parameters named by position (``?v0`` ...) rather than as the model
    names them, for PDDL that goes to Fast Downward or VAL, whose parsers reserve more words
    than PDDL does; the actions and plans are the same."""
    costs = _writes_costs(model)
    reqs = [":strips"]
    if model.neggoal or any(s.negpre for s in model.schemas.values()):
        reqs.append(":negative-preconditions")
    if tests_equality(model.schemas.values()):
        reqs.append(":equality")
    if costs:
        reqs.append(":action-costs")
    lines = [f"(define (domain {model.domain_name})", f"  (:requirements {' '.join(reqs)})"]
    consts = _constants(model)
    if consts:
        lines.append(f"  (:constants {' '.join(consts)})")
    preds = _predicate_arities(model)
    if preds:
        decl = "\n               ".join(
            f"({p}{' ' if n else ''}{_vars(n)})" for p, n in sorted(preds.items())
        )
        lines.append(f"  (:predicates {decl})")
    funcs = _function_arities(model)
    if costs:
        decl = " ".join(
            ["(total-cost) - number"]
            + [f"({f}{' ' if n else ''}{_vars(n)}) - number" for f, n in sorted(funcs.items())]
        )
        lines.append(f"  (:functions {decl})")
    for name in sorted(model.schemas):
        schema = model.schemas[name]
        if plain_variables:
            schema = rename_schema(schema, {p: f"?v{k}" for k, p in enumerate(schema.params)})
        lines.append(_action(schema, costs))
    return "\n".join(lines) + ")\n"


def problem_to_pddl(model: Model) -> str:
    """The problem file of ``model``.

    Its objects are the model's objects plus any name its atoms use, minus the domain's
    constants, so a hand-built model with an undeclared object still gives valid PDDL.
    """
    costs = _writes_costs(model)
    lines = [f"(define (problem {model.problem_name})", f"  (:domain {model.domain_name})"]
    named = {x for a in (*model.init, *model.goal, *model.neggoal, *model.functions) for x in a[1:]}
    consts = set(_constants(model))
    objects = sorted((model.objects | named) - consts)
    if objects:
        lines.append(f"  (:objects {' '.join(objects)})")
    equal = set(_equality_atoms(model, [*objects, *consts]))
    init = [atom_pddl(a) for a in sorted(model.init - equal)]
    if costs:
        init.append("(= (total-cost) 0)")
    init += [f"(= {atom_pddl(t)} {v})" for t, v in sorted(model.functions.items())]
    lines.append("  (:init " + "\n         ".join(init) + ")" if init else "  (:init)")
    goal = [atom_pddl(a) for a in sorted(model.goal)]
    goal += [f"(not {atom_pddl(a)})" for a in sorted(model.neggoal)]
    lines.append(f"  (:goal {_conj(goal, ' ' * 9)})")
    if costs:
        lines.append("  (:metric minimize (total-cost))")
    return "\n".join(lines) + ")\n"


def write_text(path: Path, text: str, *, overwrite: bool = False) -> Path:
    """Write ``text`` to ``path`` atomically (:func:`mega_sat.output.write_file`); an existing
    file is a :class:`~mega_sat.errors.UsageError` unless ``overwrite``."""
    from mega_sat.output import write_file

    return write_file(path, text, force=overwrite)


def write_model(
    model: Model,
    out_dir: str | Path,
    *,
    domain_file: str = "domain.pddl",
    problem_file: str = "problem.pddl",
    overwrite: bool = False,
) -> tuple[Path, Path]:
    """Write ``model`` as two PDDL files in ``out_dir`` (created if missing).

    Neither file is written when either one exists and ``overwrite`` is false.
    """
    from mega_sat.output import check_target

    out = Path(out_dir)
    dpath, ppath = out / domain_file, out / problem_file
    for p in (dpath, ppath):
        check_target(p, force=overwrite)
    write_text(dpath, domain_to_pddl(model), overwrite=overwrite)
    write_text(ppath, problem_to_pddl(model), overwrite=overwrite)
    return dpath, ppath
