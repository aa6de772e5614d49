within Bicycle.Mechanics;
package Rider "The rider's upper body on a hip hinge: body, hinges (free with stiffness, damping and lean torque; locked), root with the hinge speed"
  annotation(Documentation(info = "<html>
<p>Components for a rider whose upper body <code>U</code> leans relative to the rear frame
<code>B</code> about a longitudinal hip axis (Astrom, Klein, Lennartsson 2005, \"Effects of Rider
Lean\"), in the generalized coordinates of <a href=\"modelica://Bicycle.Mechanics\">Mechanics</a>:</p>
<ul>
<li><code>UpperBody</code>: the rigid upper body, its centre of mass <code>lU</code> above the hinge axis;</li>
<li><code>PartialHinge</code> (constraining class of the replaceable hinge of
<a href=\"modelica://Bicycle.Bicycles.WhippleRider\">WhippleRider</a>) with
<code>HipHinge</code> (revolute about the frame's x axis with the rider's lean torque as input and
the passive <code>SpringDamper</code>) and <code>LockedHinge</code> (the upper body rigidly fixed to
the rear frame at the initial lean angle; the lean torque has no effect);</li>
<li><code>Ground</code>: the root of a bicycle with the hinge, with the lean angle as a seventh
generalized coordinate and its rate as a fourth independent speed.</li>
</ul>
</html>"));
end Rider;
