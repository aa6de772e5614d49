within Bicycle.Wheels;
model KnifeEdge "Knife-edge wheel: contact point at distance r from the centre, straight down in the wheel plane"
  extends Bicycle.Wheels.PartialWheel;
equation
  rho = r*e;
  rho_dot = r*e_dot;
  annotation(
    Icon(graphics = {
      Ellipse(extent = {{44, -76}, {52, -28}}, lineColor = {0, 0, 0}, fillColor = {64, 64, 64}, fillPattern = FillPattern.Solid)}),
    Documentation(info = "<html><p>The wheel of the Whipple bicycle of Meijaard et al. (2007):
a rigid disc of radius <code>r</code> with a sharp edge, <code>rho = r e</code>.</p></html>"));
end KnifeEdge;
