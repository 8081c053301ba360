"""Reading and writing PDDL: domain and problem files into lifted models, plans, task folders."""
