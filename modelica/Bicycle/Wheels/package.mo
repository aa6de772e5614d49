within Bicycle;
package Wheels "Replaceable wheel models: knife edge, torus, crowned roller"
  extends Bicycle.Icons.Package;
  annotation(Documentation(info = "<html><p>Rigid axisymmetric wheels rolling without slip on the flat
ground, for the generalized-coordinate components of <a href=\"modelica://Bicycle.Mechanics\">Mechanics</a>.
They differ only in the vector <code>rho</code> from the wheel centre to the contact point:
<code>KnifeEdge</code> <code>rho = r e</code>, <code>Torus</code> (tyre with crown radius
<code>t</code>) <code>rho = (r - t) e + t e_z</code>, <code>Roller</code> (crowned roller of rocking radius
<code>R</code>, Astrom et al. 2005, eq (27)) the same geometry with <code>R</code> not bounded by the
wheel radius. <code>e</code> is the unit vector in the wheel plane pointing most steeply down.</p></html>"));
end Wheels;
