"""The compiled loop's elements: the column layout of the plan's tables and one numba-jitted
function family per module (measurements, diameter calculators, controllers, dancers, splices,
brakes), called every tick or every right-hand side."""
