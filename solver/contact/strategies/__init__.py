"""How the contact systems are reduced before Newton runs on them: the
nested start on Γc (:mod:`.nested`) and the candidate screening, for
frictionless contact (:mod:`.candidates`) and for friction
(:mod:`.friction_candidates`), and for two bodies the frictionless
candidates from K's own factor (:mod:`.bordered`)."""
