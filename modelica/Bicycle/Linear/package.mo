within Bicycle;
package Linear "Components of the linearized Whipple bicycle (Meijaard et al. 2007): bodies contributing to M, C1, K0, K2"
  annotation(Documentation(info = "<html>
<p>The linearized Whipple bicycle of Meijaard, Papadopoulos, Ruina and Schwab (2007), eq (24) of
Astrom, Klein and Lennartsson (2005),</p>
<pre>  M q'' + v C1 q' + (g K0 + v^2 K2) q = f,   q = [phi; delta],</pre>
<p>assembled from components. For a fixed geometry (wheelbase w, trail c, steer-axis tilt lam)
M, C1, K0 and K2 are linear in the bodies' masses, first moments and inertias: each body
(<a href=\"modelica://Bicycle.Linear.RearWheel\">RearWheel</a>,
<a href=\"modelica://Bicycle.Linear.RearFrame\">RearFrame</a>,
<a href=\"modelica://Bicycle.Linear.FrontFrame\">FrontFrame</a>,
<a href=\"modelica://Bicycle.Linear.FrontWheel\">FrontWheel</a>) carries its own mass properties
and computes its part of the four matrices from Meijaard's Appendix A. Through its
<a href=\"modelica://Bicycle.Linear.RollSteer\">RollSteer</a> connector it sees the roll and steer
angles and rates and delivers its generalized inertia (flow M) and its generalized force
-(v C1 q' + (g K0 + v^2 K2) q) (flow Q). A connection set sums the flows (Kane's equations in
linear form); <a href=\"modelica://Bicycle.Linear.Coordinates\">Coordinates</a> solves the summed
M q'' = Q for the accelerations, <a href=\"modelica://Bicycle.Linear.Torques\">Torques</a> applies
the roll and steer torques.</p>
<p>Sign conventions are those of Meijaard (2007): axes x forward, y right, z down, origin at the
rear contact point; roll and steer positive to the right. Flows are positive into a component
(Modelica convention): a body delivers -M_i and +(v C1_i q' + (g K0_i + v^2 K2_i) q).</p>
</html>"));
end Linear;
