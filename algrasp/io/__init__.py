"""Adapters for what goes in and out: CAD drawings and meshes (``cad``) and run records
(``record``). They call geometry and planning; nothing below imports them."""
