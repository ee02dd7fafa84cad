"""Coulomb friction by load steps, thesis §5: the load step's system
(:mod:`.system`, shared by the thesis's split :mod:`.split` and the
projection formulation :mod:`.projection`; in 3D on a condensed S
:mod:`.disc`), the start of a condensed step (:mod:`.start`), the reduced
Newton direction (:mod:`.newton`), one load step (:mod:`.steps`), the
completed steps delivered in order (:mod:`.stream`) and the driver
(:mod:`.driver`)."""
