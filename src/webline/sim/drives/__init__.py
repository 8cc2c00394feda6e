"""What the drives do each controller tick in the compiled loop: measure (noise,
quantisation), calculate diameters, and command torques (the cascaded PI and its feedforward,
the decentralized families, MRAC, the tension observer, taper through a dancer, centre-winder
compensations, a user's controller); built on ``sim.elements``."""
