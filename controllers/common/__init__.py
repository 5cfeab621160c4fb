"""What several controllers share: the hop gradient's broadcast fields (gradient), a
formation's trip to the target (formation, formationkernel), edge-following watches (edges),
the local floor map (localmap, mapkernel), the push away from close neighbours (push) and
numpy's summation compiled (npsum). No controller imports another; they import from here."""
