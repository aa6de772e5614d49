within Bicycle.Wheels;
model Roller "Crowned roller with rocking radius R (Astrom, Klein, Lennartsson 2005, eq (27) and Figure 21)"
  extends Bicycle.Wheels.PartialWheel;
  parameter Bicycle.Units.Length R(min = 1e-6) = 0.4 "Rocking radius: radius of the lateral curvature of the roller";
equation
  rho[1] = (r - R)*e[1];
  rho[2] = (r - R)*e[2];
  rho[3] = (r - R)*e[3] + R;
  rho_dot = (r - R)*e_dot;
  annotation(
    Icon(graphics = {
      Rectangle(extent = {{24, -66}, {76, -34}}, lineColor = {0, 0, 0}, fillColor = {64, 64, 64}, fillPattern = FillPattern.Solid, radius = 16)}),
    Documentation(info = "<html>
<p>The crowned roller of the adapted bicycles of Astrom, Klein and Lennartsson (2005), section
\"Adapted Bicycles for Teaching Children with Disabilities\", Figure 21: a wide roller whose lateral
profile is a circular arc of radius <code>R</code> (the rocking radius) with its centre on the
roller's middle plane, at the height <code>R</code> above the ground when the roller is upright.
Eq (27) there, <code>p = sqrt(m g (h - R)/J)</code>, is the consequence for the lean dynamics: leaning by
<code>phi</code> rolls the roller on its arc, the contact point moves sideways, the centre of mass
(height <code>h</code>) moves by only <code>(h - R) sin(phi)</code> relative to it, and gravity acts
with the moment <code>m g (h - R) sin(phi)</code> instead of <code>m g h sin(phi)</code>.</p>
<p>This model is the three-dimensional contact geometry of that profile: the roller is the solid of
revolution of the arc about the axle, the arc centre at <code>r - R</code> from the axle along the
most steeply downward direction <code>e</code> of the roller plane (above the axle if
<code>R &gt; r</code>). The contact point is <code>rho = (r - R) e + R e_z</code> from the centre: the same
formula as <code>Torus</code>, but the rocking radius is not bounded by the roller radius (the
torus' crown radius is, <code>t &le; r</code>) and it is a parameter of the roller's shape rather
than of a tyre. Its width is taken to be large enough for the contact to stay on the arc.</p>
</html>"));
end Roller;
