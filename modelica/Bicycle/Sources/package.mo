within Bicycle;
package Sources "Signal sources for co-simulation systems (twins of cosim's Python sources)"
end Sources;
