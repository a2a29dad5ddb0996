"""Past self-contact: the rod followed through the first self-contact.

* :mod:`.centreline` -- r(s, t) and the frame reconstructed at each step from the 12 fields
  (spatial route of section 4), and the drift of that reconstruction;
* :mod:`.topology` -- link, twist and writhe (Calugareanu-White-Fuller, Lk = Tw + Wr);
* :mod:`.law` -- the contact law: a penalty spring-dashpot between parts of the rod farther
  apart than a few diameters along it, with an O(N log N) broad phase;
* :mod:`.run` -- :class:`~.run.Contact`, :class:`~.run.ContactScene` and
  :func:`~.run.run_contact_scene`: a buckling scene run past contact;
* :mod:`.checks` -- the issue's bounds and a run's verdict on them, each reading beside
  its bound.

A scene without contact computes none of this: :func:`dyntorsion.buckling.simulate` and
:class:`dyntorsion.buckling.Scene` are untouched and their records unchanged.
"""
