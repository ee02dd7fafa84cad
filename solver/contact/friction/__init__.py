"""Coulomb friction by load steps, thesis §5: the load step's system
(:mod:`.system`; in 3D on a condensed S :mod:`.disc`), its reduced Newton
direction (:mod:`.newton`), one load step (:mod:`.steps`), the completed
steps delivered in order (:mod:`.stream`) and the driver (:mod:`.driver`)."""
