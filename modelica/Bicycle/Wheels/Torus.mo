within Bicycle.Wheels;
model Torus "Toroidal wheel (tyre with crown radius t): contact point (r - t) e + t e_z from the centre"
  extends Bicycle.Wheels.PartialWheel;
  parameter Bicycle.Units.Length t(min = 0) = 0 "Crown radius of the tyre (radius of the tube; 0: knife edge)";
equation
  rho[1] = (r - t)*e[1];
  rho[2] = (r - t)*e[2];
  rho[3] = (r - t)*e[3] + t;
  rho_dot = (r - t)*e_dot;
  annotation(
    Icon(graphics = {
      Ellipse(extent = {{30, -70}, {66, -34}}, lineColor = {0, 0, 0}, fillColor = {64, 64, 64}, fillPattern = FillPattern.Solid),
      Ellipse(extent = {{40, -60}, {56, -44}}, lineColor = {0, 0, 0}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid)}),
    Documentation(info = "<html><p>A wheel whose tyre is a torus: the tube centre circle has
the radius <code>r - t</code>, the tube (crown) the radius <code>t</code>, so the centre of the upright
wheel is at the height <code>r</code> for every <code>t</code>. The contact point is the point of the
tube below the tube centre: <code>rho = (r - t) e + t e_z</code>. <code>t = 0</code> gives the knife
edge (with the same equations: the result is the knife edge's to rounding).</p></html>"));
end Torus;
