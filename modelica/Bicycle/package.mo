within;
package Bicycle "Bicycle dynamics and control after Astrom, Klein and Lennartsson (IEEE CSM 2005)"
  annotation(
    version = "0.1.0",
    Documentation(info = "<html>
<p>Component models of a bicycle (rear frame with rider, front fork, wheels, leaning rider)
assembled into the models of K. J. Astrom, R. E. Klein and A. Lennartsson, <em>Bicycle Dynamics
and Control</em>, IEEE Control Systems Magazine 25(4), 2005. Equation numbers in the descriptions
refer to that paper.</p>
<p>Sign conventions: the second-order models follow the paper (ISO 8855: x forward, y left, z up;
steer angle positive to the left), the Whipple family follows Meijaard et al. (2007) (x forward,
y right, z down; steer angle positive to the right); roll angles agree. See
<a href=\"modelica://Bicycle.UsersGuide.Conventions\">UsersGuide.Conventions</a>.</p>
<p>Models marked with the vendor annotation <code>__Cosim(export = true)</code> are exported as
FMUs by <code>cosim build</code>.</p>
</html>"));
end Bicycle;
