"""Frictionless contact, thesis (67): the system (:mod:`.system`), its
condensed Newton direction (:mod:`.newton`) and the driver
(:mod:`.driver`)."""
