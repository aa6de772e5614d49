within Bicycle;
package Linear "Components of the linearized Whipple bicycle (Meijaard et al. 2007): bodies contributing to M, C1, K0, K2"
  extends Bicycle.Icons.Package;
  annotation(Documentation(info = "<html>
<p>The linearized Whipple bicycle of Meijaard, Papadopoulos, Ruina and Schwab (2007), eq (24) of
Astrom, Klein and Lennartsson (2005),</p>
<pre>  M q'' + v C1 q' + (g K0 + v^2 K2) q = f,   q = [phi; delta],</pre>
<p>assembled from components. For a fixed geometry (wheelbase w, trail c, steer-axis tilt lam)
M, C1, K0 and K2 are linear in the bodies' masses, first moments and inertias: each body
(<a href=\"modelica://Bicycle.Linear.RearWheel\">RearWheel</a>,
<a href=\"modelica://Bicycle.Linear.LinearizedRearFrame\">LinearizedRearFrame</a>,
<a href=\"modelica://Bicycle.Linear.LinearizedFrontFrame\">LinearizedFrontFrame</a>,
<a href=\"modelica://Bicycle.Linear.FrontWheel\">FrontWheel</a>) carries its own mass properties
and computes its part of the four matrices from Meijaard's Appendix A. Through its
<a href=\"modelica://Bicycle.Linear.RollSteer_a\">RollSteer_a</a> connector it receives the roll
and steer angles and rates (inputs) and delivers, as flow Q, the generalized force that keeps it in
d'Alembert equilibrium, Q_i = M_i q'' + v C1_i q' + (g K0_i + v^2 K2_i) q, in which the
accelerations q'' are the connector's potentials. <a href=\"modelica://Bicycle.Linear.Torques\">Torques</a>
delivers -[T_phi; T_delta]. <a href=\"modelica://Bicycle.Linear.Coordinates\">Coordinates</a>
gives the states to the set through its <a href=\"modelica://Bicycle.Linear.RollSteer_b\">RollSteer_b</a>
connector (outputs) and adds no force of its own, so the flow sum of the connection set is eq (24)
itself (Kane's equations in linear form) and determines the accelerations, which Coordinates
returns as signals.</p>
<p>The connectors are balanced (Modelica Language Specification 9.3.1): the kinematics that the
states fix are passed causally, as matching inputs and outputs, and only the acceleration and
the generalized force of each coordinate form an acausal potential/flow pair. Each component is
therefore balanced on its own and can be checked standalone by a Modelica tool.</p>
<p>Sign conventions are those of Meijaard (2007): axes x forward, y right, z down, origin at the
rear contact point; roll and steer positive to the right. Flows are positive into a component
(Modelica convention): Q is the generalized force exerted on the component through its
connector.</p>
</html>"));
end Linear;
