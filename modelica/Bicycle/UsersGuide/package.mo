within Bicycle;
package UsersGuide "User's Guide"
  extends Bicycle.Icons.Information;
  annotation(Documentation(info = "<html>
<p>The library models the bicycle of K. J. &Aring;str&ouml;m, R. E. Klein and A. Lennartsson,
<em>Bicycle Dynamics and Control</em>, IEEE Control Systems Magazine 25(4), 2005, from the paper's
second-order models to the nonlinear Whipple bicycle of its eq (26), as components that are connected
into bicycles and compiled into FMUs by the <code>cosim</code> tool.</p>
<ul>
<li><a href=\"modelica://Bicycle.UsersGuide.Conventions\">Conventions</a>: axes, signs, angles, units
(read this first: the simple models and the Whipple family use different sign conventions).</li>
<li><a href=\"modelica://Bicycle.UsersGuide.Structure\">Structure</a>: the packages and how the
components connect.</li>
<li><a href=\"modelica://Bicycle.UsersGuide.Variants\">Variants</a>: how to make another bicycle in a
few lines.</li>
</ul>
</html>"));
end UsersGuide;
